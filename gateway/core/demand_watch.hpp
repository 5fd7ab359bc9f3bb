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
#include "gateway/core/urgency_demand.hpp"
#include "gateway/core/wire_model.hpp"

namespace tgw::core {

/// Whether `now` differs from `told` enough to say so again: some urgency's bit/s moved by more than `fraction`
/// of what was told and by more than `floor_bps` (an urgency that appeared or went counts from zero).
bool demand_changed(const std::vector<UrgencyDemand>& told, const std::vector<UrgencyDemand>& now, double fraction,
                    double floor_bps);

/// The span a robot's demand is worked out over, by its gateway (DemandWatch) and by the base camp's grantor.
inline constexpr base::Duration DEMAND_WINDOW = std::chrono::seconds(2);

class DemandWatch {
  public:
    struct Config {
        base::Duration window = DEMAND_WINDOW;  ///< the demand now is over this much of the recent past
        double fraction = 0.25;                 ///< see demand_changed()
        double floor_bps = 1000;
    };

    DemandWatch(Config config, WireModel wire);

    /// The topics' counts at `now`, as a status would carry them, once a status period. True when a status should
    /// go now for the demand's sake, and every time until one status has left: a base camp that has heard none
    /// grants the robot nothing of its own (a gateway that restarted made one status, which expired behind its
    /// discovery's traffic, and its next waited for the spacing: 50 s at 6,000 bit/s). Never while the last
    /// status's fate is unknown.
    bool changed(base::SteadyTime now, const std::vector<TopicLoad>& loads);
    /// A status with `loads` was made at `at`; it tells the base camp once delivered() says it left.
    void sent(base::SteadyTime at, std::vector<TopicLoad> loads);
    /// The status of the last sent() left for the base camp (true), or was dropped before it could (false): the
    /// base camp grants from the statuses it gets, so a dropped one told it nothing.
    void delivered(bool left);
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
};

}  // namespace tgw::core
