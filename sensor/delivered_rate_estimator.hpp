#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "base/clock.hpp"

namespace tgw::sensor {

/// One sample of what went into the link and what came of it. Cumulative counters may wrap or reset (an
/// interface re-created): the estimator then starts afresh from that sample.
struct LinkCounters {
    std::uint64_t gateway_sent_bytes = 0;  ///< cumulative: what the gateway wrote, as its wire model counts it
    std::uint64_t tx_bytes = 0;            ///< cumulative: the WAN interface's transmit counter
    std::uint64_t drops = 0;               ///< cumulative: packets the root qdisc dropped
    std::uint64_t backlog_bytes = 0;       ///< now: bytes waiting in the root qdisc
};

/// The AIMD of DeliveredRateEstimator. The defaults react within about a second on the paper's 10..70 kbit/s
/// links and take about 10 s to win back a 20 % cut.
struct DeliveredRateConfig {
    /// Multiplicative decrease on congestion, in (0, 1).
    double decrease_factor = 0.8;
    /// Additive increase, as a fraction of the sensor's rate per second of congestion-free sending.
    double increase_fraction_per_s = 0.02;
    /// A backlog the link needs longer than this to drain (at the budget's rate) is congestion...
    base::Duration max_queue_delay = std::chrono::milliseconds(250);
    /// ...but never less than this many bytes: two full Ethernet frames queued are normal on a slow link.
    std::uint64_t min_backlog_bytes = 3'028;
    /// At most one decrease per interval: the queue needs time to drain before the last cut can show.
    base::Duration decrease_interval = std::chrono::seconds(1);
    /// The cap never goes below this fraction of the sensor's rate, in (0, 1].
    double min_cap_fraction = 0.1;
    /// Raise the cap only when the gateway sent at least this fraction of it: an idle link proves nothing.
    double min_utilisation = 0.5;
    /// The delivered rate is measured over windows at least this long: shorter ones see a shaper's bursts.
    base::Duration delivered_window = std::chrono::seconds(1);

    /// "" when usable, else what is wrong, naming the field.
    std::string validate() const;
};

enum class LinkVerdict {
    unknown,     ///< no interval measured yet
    delivering,  ///< no drops, the backlog small: the link carries what it is given
    draining,    ///< the backlog is too long but shrinking: waiting for the last cut to show
    congested,   ///< drops, or a long and growing backlog: the link delivers less than the budget
};

/// Closes the loop over a rate sensor: from periodic samples of the gateway's and the kernel's counters it
/// decides whether the link delivers what the sensor claims and, when it does not, caps the budget below the
/// claim (multiplicative decrease while drops or backlog persist, additive increase once they stop, the cap
/// lifted once it reaches the claim). A cut never goes below decrease_factor times what the link was last seen to
/// deliver: a link that drops while it carries 20 kbit/s can carry about that much, and persistent congestion
/// that someone else causes must not drive the budget to the floor. Pure logic on the injected clock; the
/// counters come from the caller.
class DeliveredRateEstimator {
  public:
    /// Throws base::ConfigError when `config` is invalid. `clock` must outlive the estimator.
    DeliveredRateEstimator(DeliveredRateConfig config, const base::Clock& clock);

    /// Takes one sample at clock.now() with the sensor's current rate; returns the rate the budget should use:
    /// the claim, or the cap when that is lower. A claim that is not a finite rate >= 0 gives 0 and leaves the state as
    /// is.
    double update(const LinkCounters& counters, double claimed_bps);

    /// The cap over the sensor's reading; nullopt when the link delivers what the sensor says.
    std::optional<double> cap_bps() const { return cap_bps_; }
    /// What the interface transmitted over the last full delivered_window, bit/s; nullopt before one.
    std::optional<double> delivered_bps() const { return delivered_bps_; }
    LinkVerdict verdict() const { return verdict_; }

  private:
    struct Sample {
        base::SteadyTime at;
        LinkCounters counters;
    };

    double budget(double claimed_bps) const;

    DeliveredRateConfig config_;
    const base::Clock& clock_;
    std::optional<Sample> previous_;
    std::optional<Sample> window_start_;
    std::optional<double> cap_bps_;
    std::optional<double> delivered_bps_;
    std::optional<base::SteadyTime> last_decrease_;
    LinkVerdict verdict_ = LinkVerdict::unknown;
};

}  // namespace tgw::sensor
