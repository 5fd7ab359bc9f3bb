// When a fleet's gateway should tell the base camp of its demand sooner than its status spacing allows
// (--channel-grants). The base camp grants from the demand between a gateway's last two statuses (urgency_demand),
// and a status takes at most 2 % of the rate, so on a 15,000 bit/s share one comes every 10 s or so: a robot whose
// hazards start would wait that long for its share. The watch keeps what the base camp was last told and the
// demand of the last few seconds, and says when they differ enough to send a status now.
#pragma once

#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include "base/time.hpp"
#include "core/urgency_demand.hpp"
#include "core/wire_model.hpp"

namespace tgw::core {

/// Whether `now` differs from `told` enough to say so again: some urgency's bit/s moved by more than `fraction`
/// of what was told and by more than `floor_bps` (an urgency that appeared or went counts from zero).
bool demand_changed(const std::vector<UrgencyDemand>& told, const std::vector<UrgencyDemand>& now, double fraction,
                    double floor_bps);

/// Whether `now` holds an urgency above `floor_bps` more urgent than every one `told` holds above it: a robot whose
/// hazards start after it told the base camp of its pictures only, or of nothing.
bool more_urgent_than_told(const std::vector<UrgencyDemand>& told, const std::vector<UrgencyDemand>& now,
                           double floor_bps);

/// The span a robot's demand is worked out over, by its gateway (DemandWatch) and by the base camp's grantor.
inline constexpr base::Duration DEMAND_WINDOW = std::chrono::seconds(2);

class DemandWatch {
  public:
    struct Config {
        base::Duration window = DEMAND_WINDOW;  ///< the demand now is over this much of the recent past
        double fraction = 0.25;                 ///< see demand_changed()
        double floor_bps = 1000;
        /// The most of the rate statuses made for the demand's sake may take. Unbounded, a robot on a small share
        /// sent one a second while its demand grew at a fleet's start: a compact status is half a second of wire
        /// at 12,000 bit/s, and B (TTL 2 s) expired behind them (three robots at 60,000 bit/s, the measuring
        /// relay's slow start: B 197 of 200 on two robots, all lost at 3.7 to 4.3 s).
        double rate_share = 0.2;
    };

    DemandWatch(Config config, WireModel wire);

    /// The topics' counts at `now`, as a status would carry them, once a status period. True when a status should
    /// go now for the demand's sake, and every time until one status has left: a base camp that has heard none
    /// grants the robot nothing of its own (a gateway that restarted made one status, which expired behind its
    /// discovery's traffic, and its next waited for the spacing: 50 s at 6,000 bit/s). Never while the last
    /// status's fate is unknown, nor sooner after the last status left than Config::rate_share of `rate_bps`
    /// allows for its bits, unless the demand is more urgent than any the base camp was told
    /// (more_urgent_than_told): a share granted for less urgent samples, or the floor of a robot that was quiet,
    /// cannot carry them, and the status asking for more is what they wait for (three robots under grants, their
    /// publishers' Lifespans as TTLs: rover1's A began 1.7 s after a status that told nothing, its floor of
    /// 3,086 bit/s held its next status back 4 s, and 3 A and 9 B expired).
    bool changed(base::SteadyTime now, const std::vector<TopicLoad>& loads, double rate_bps);
    /// A status with `loads`, `wire_bits` on the wire, was made at `at`; it tells the base camp once delivered()
    /// says it left.
    void sent(base::SteadyTime at, std::vector<TopicLoad> loads, double wire_bits);
    /// The status of the last sent() left for the base camp (true), or was dropped before it could (false), as
    /// seen at `seen_at`: the base camp grants from the statuses it gets, so a dropped one told it nothing, and
    /// cost the link nothing. The spacing Config::rate_share asks for counts from when one left: a status that
    /// waited in the queue and left just before the next was made would otherwise go back to back with it.
    void delivered(bool left, base::SteadyTime seen_at);
    /// Whether the last status's fate is still unknown.
    bool pending() const { return pending_.has_value(); }

    /// What the base camp was last told: the demand between the last two statuses.
    const std::vector<UrgencyDemand>& told() const { return told_; }

  private:
    using Snapshot = std::pair<base::SteadyTime, std::vector<TopicLoad>>;

    const Config config_;
    const WireModel wire_;
    std::deque<Snapshot> recent_;        ///< the window's snapshots, and the last one before it
    std::optional<Snapshot> pending_;    ///< made, not yet known to have left
    std::optional<Snapshot> last_sent_;  ///< the last that left
    std::vector<UrgencyDemand> told_;
    double pending_bits_ = 0.0;  ///< the wire bits of the status pending_ stands for
    /// When the last status that left was seen to have, and its bits on the wire.
    std::optional<std::pair<base::SteadyTime, double>> last_left_;
};

}  // namespace tgw::core
