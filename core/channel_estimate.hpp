// What a fleet's shared channel delivers, as the base camp measures it (issue 21, part 3): the rate the grants
// split, instead of the rate someone typed in. Pure: the base camp feeds it what arrived and when it left.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "base/clock.hpp"
#include "base/time.hpp"

namespace tgw::core {

/// The AIMD of ChannelEstimate. The defaults cut within two seconds of a queue forming on the paper's channels and
/// win back a tenth of the bound in five seconds of clear channel.
struct ChannelEstimateConfig {
    /// A cut takes the estimate to this fraction of what the channel delivered meanwhile (and at least 5 % down),
    /// in (0, 1).
    double decrease_factor = 0.9;
    /// Growth per second of clear channel, as a fraction of the upper bound.
    double increase_fraction_per_s = 0.02;
    /// The slow start: the estimate begins at this fraction of the upper bound, in (0, 1], and grows by
    /// start_growth_per_s of itself a second while the robots use it and the channel is clear, until the first
    /// short queue (hold_queueing) or loss, where it falls to what the channel delivered. Begun at the bound
    /// (120,000 bit/s for a 60,000 channel), three robots that started at once sent 1.8 times what the channel
    /// carried, the queue reached 564 ms, and rover1 lost 11 hazards in 3 s. 1: no slow start.
    double start_fraction = 0.25;
    /// A quarter of itself a second overshot to 103,000 bit/s before the first queue showed at the camp.
    double start_growth_per_s = 0.1;
    /// Samples that waited this much longer than their sender's quickest ever did: the channel queues.
    base::Duration max_queueing = std::chrono::milliseconds(250);
    /// Samples that waited longer than this, but not max_queueing: the channel is full, and the estimate eases down
    /// (up to increase_fraction_per_s at max_queueing); below it, it grows, the slower the nearer the queue is to it.
    base::Duration hold_queueing = std::chrono::milliseconds(100);
    /// At most one cut per interval: the new grants must reach the robots and the queue drain before a cut shows.
    base::Duration decrease_interval = std::chrono::seconds(2);
    /// The estimate never goes below this fraction of the upper bound, in (0, 1].
    double min_fraction = 0.1;
    /// Grow only while the channel carried at least this fraction of the estimate: an idle channel proves nothing,
    /// and neither does one the robots use less than they could. Robots that use all of it deliver about 0.86 of
    /// it (the newcomers' tenth kept back, 95 % budgeted), more with their traffic outside the schedule. Judged
    /// against the grants instead (0.7 of them; the grants hand out the whole estimate, used or not), the estimate
    /// grew to 85,000 bit/s on a 60,000 channel while a robot was away, and its return met a queue of 461 ms; at
    /// 0.85 of the estimate it grew back too slowly after a cut (two robots' hazards 252 to 287 of 300 on time).
    double min_utilisation = 0.8;
    /// The queueing is measured over intervals at least this long.
    base::Duration interval = std::chrono::seconds(1);
    /// The delivered rate over this long: a second holds a few large frames, or none.
    base::Duration delivered_window = std::chrono::seconds(3);
    /// A sender's quickest delay is remembered this long (in five steps): the two clocks drift apart.
    base::Duration baseline_window = std::chrono::minutes(5);
    /// A sender this new may have joined a standing queue, its quickest delay a queued one: while others known
    /// longer tell the queue, its own delays do not count, and its quickest is taken as its delay less the queue
    /// they tell. Counted, a gateway restarted into a 600 ms queue read 0 and hid it for 8 s (measuring relay,
    /// three robots: the others' hazards 200 to 800 ms in the router, rover1 195 of 200 on time).
    base::Duration joining = std::chrono::seconds(10);

    /// "" when usable, else what is wrong, naming the field.
    std::string validate() const;
};

enum class ChannelVerdict {
    unknown,   ///< no interval measured yet
    clear,     ///< nothing lost, no queue: the channel carries what it is given
    full,      ///< a short queue: the channel carries what it is given, and no more; the estimate eases down
    draining,  ///< a queue, shrinking since the last cut
    queueing,  ///< a queue that does not shrink: the grants add up to more than the channel delivers
    losing,    ///< samples lost on the way (gaps in the writers' sequence numbers)
};

/// "clear", "queueing", ...
const char* to_string(ChannelVerdict verdict);

/// The rate of a fleet's shared channel, from what the base camp receives: the bytes that arrive (delivered),
/// the samples lost on the way, and how long samples took from their sender, each sender's delay taken above the
/// least it ever took, so that the two clocks' offset cancels. Starts at a fraction of the upper bound (the
/// channel's nominal rate) and grows by a part of itself a second until the first queue (a slow start); then cuts to
/// a fraction of what the channel delivered while it queued long or lost, eases down while a short queue stands, and
/// grows back slowly while the robots use it and samples cross with less (not while no sample tells); never above
/// the bound.
/// Not thread-safe.
class ChannelEstimate {
  public:
    /// Throws base::ConfigError when `config` is invalid or `upper_bps` is not a rate above 0. `clock` must
    /// outlive the estimate.
    ChannelEstimate(double upper_bps, ChannelEstimateConfig config, const base::Clock& clock);

    /// One sample of `wire_bytes` from `sender`, which arrived `one_way` after its sender stamped it (the
    /// receiver's clock less the sender's: it may be negative).
    void arrived(const std::string& sender, base::Duration one_way, std::size_t wire_bytes);

    /// At clock.now(): a participant joined the WAN domain. Its discovery crosses the channel before any sample of
    /// it arrives (arrived()); for config_.joining it counts as a sender that joins (cut()).
    void participant_joined() { participant_joined_ = clock_.now(); }

    /// At clock.now(): everything the channel delivered so far (wire bytes, cumulative) and the samples lost so
    /// far (cumulative), while the grants handed out added up to `granted_bps`. Returns the estimate.
    double update(std::uint64_t delivered_wire_bytes, std::uint64_t lost_samples, double granted_bps);

    double channel_bps() const { return estimate_bps_; }
    double upper_bps() const { return upper_bps_; }
    /// What the channel delivered over the last delivered_window, bit/s; nullopt before an interval.
    std::optional<double> delivered_bps() const { return delivered_bps_; }
    /// The standing queue of the last interval (the least any sample in it waited); nullopt without samples.
    std::optional<base::Duration> queueing() const { return queueing_; }
    ChannelVerdict verdict() const { return verdict_; }

  private:
    /// A sender's quickest delays, one per step of baseline_window / BASELINE_STEPS.
    struct Baseline {
        static constexpr int STEPS = 5;
        base::SteadyTime joined{};
        base::SteadyTime step_start{};
        base::Duration minimum[STEPS]{};
        int steps = 0;  ///< how many of minimum[] hold a value; minimum[0] is the current step's
        std::optional<base::Duration> interval_quickest;  ///< while it joins: its quickest delay this interval
        base::Duration least() const;
        bool joining(base::SteadyTime now, base::Duration window) const { return now - joined < window; }
    };
    struct Counters {
        base::SteadyTime at{};
        std::uint64_t delivered_wire_bytes = 0;
        std::uint64_t lost_samples = 0;
    };

    /// `burst`: the queue may be a joining sender's discovery, which the camp does not all see (cut() says why).
    void cut(double delivered_bps, base::SteadyTime now, bool burst);
    /// A sender or a participant joins (config_.joining) while senders known longer send: a gateway restarted, or a
    /// robot new to the running fleet.
    bool joined_lately(base::SteadyTime now) const;
    /// The standing queue of the interval just ended: the senders known longer than config_.joining tell it where
    /// they sent, and the queue they tell corrects the joining senders' quickest delays. Starts the next interval.
    std::optional<base::Duration> end_interval(base::SteadyTime now);
    /// The estimate after an interval of `elapsed` on a clear channel that carried `delivered_bps` (over the
    /// delivered window; in the slow start over the interval) with `queueing`.
    double grown(base::Duration elapsed, double delivered_bps, base::Duration queueing) const;

    const ChannelEstimateConfig config_;
    const base::Clock& clock_;
    const double upper_bps_;
    double estimate_bps_;
    std::map<std::string, Baseline> baselines_;
    std::optional<base::Duration> interval_queueing_;  ///< the least queueing of the interval so far
    std::optional<base::Duration> joining_queueing_;   ///< the same, of the senders still joining
    std::optional<Counters> last_;
    std::deque<Counters> window_;  ///< the updates of the last delivered_window
    /// The delivered rate of each update of the last config_.joining, for a cut behind a joining sender's burst.
    std::deque<std::pair<base::SteadyTime, double>> recent_delivered_;
    std::optional<double> delivered_bps_;
    std::optional<base::Duration> queueing_;
    std::optional<base::SteadyTime> last_cut_;
    std::optional<base::SteadyTime> participant_joined_;
    ChannelVerdict verdict_ = ChannelVerdict::unknown;
    bool starting_ = false;  ///< in the slow start: no queue seen yet (set by the constructor)
};

}  // namespace tgw::core
