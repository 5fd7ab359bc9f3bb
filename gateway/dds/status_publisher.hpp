// The gateway's status (STATUS_TOPIC): when one is made, and what it says of the schedule.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "GatewayStatus.h"
#include "base/clock.hpp"
#include "core/demand_watch.hpp"
#include "core/forwarding_loop.hpp"
#include "core/wire_model.hpp"
#include "gateway/dds/topic_accounting.hpp"

namespace tgw::dds {

/// Looked at every status period, a status is made once the spacing the rate allows now has passed since the last
/// (at most STATUS_RATE_SHARE of the rate): a spacing fixed when a status was made during an outage (minutes at
/// 1,000 bit/s) would silence it for as long after the link came back. With --channel-grants also when the robot's
/// demand has moved away from what the base camp was last told (DemandWatch): its share follows within a status
/// period, not a spacing. The status goes to the loop as a sample of its topic, scheduled like any other. Not
/// thread-safe: the Gateway's worker loop calls it.
class StatusPublisher {
  public:
    struct Config {
        base::Duration period{};
        std::string robot_name;
        bool compact_wan = false;
        /// --channel-grants: the demand is watched, and the least share follows each status.
        bool channel_grants = false;
        core::WireModel wire;
        double budget_fraction = 1.0;
    };
    /// What the status says beyond the schedule, from the Gateway.
    struct Sources {
        /// The status's rows: the topics bridged now, and the retired ones in one row.
        std::function<std::vector<TopicCount>()> rows;
        /// The gateway's own fields (its WAN prefix, sensor, traffic outside the schedule, uplink, log, backfill,
        /// matched readers), given the status with its rows and the base-camp readers those rows have.
        std::function<void(idl::GatewayStatus&, std::int32_t rows_readers)> fill;
        /// The least share the gateway budgets for under a grant (core::least_share_bps) changed, with
        /// --channel-grants: before the status goes to the loop, so the rate leaves room for it.
        std::function<void(double least_share_bps)> least_share;
    };

    StatusPublisher(Config config, core::ForwardingLoop& loop, core::TopicId topic, const base::Clock& clock,
                    Sources sources);

    /// Makes a status if one is due at `now` and submits it to the loop.
    void look(std::chrono::steady_clock::time_point now);
    /// Statuses made so far.
    std::uint64_t published() const { return published_.load(); }
    /// The time between statuses at `rate_bps` for a status of `wire_bits` on the wire: the status period, longer
    /// where a status would take more than STATUS_RATE_SHARE of the rate.
    base::Duration spacing(double rate_bps, double wire_bits) const;

  private:
    /// Whether the demand the base camp was last told of has moved (or a status is pending and its fate known).
    bool demand_moved(std::chrono::steady_clock::time_point now, double rate_bps,
                      std::optional<std::vector<TopicCount>>& rows, std::vector<core::TopicLoad>& loads);

    Config config_;
    core::ForwardingLoop& loop_;
    core::TopicId topic_;
    const base::Clock& clock_;
    Sources sources_;
    std::atomic<std::uint64_t> published_{0};
    std::optional<std::chrono::steady_clock::time_point> last_at_;
    double last_wire_bits_ = 0.0;                    ///< the last status's size on the wire
    std::optional<core::DemandWatch> demand_watch_;  ///< with --channel-grants
    std::uint64_t forwarded_seen_ = 0;               ///< the status topic's counts when the last status was made
    std::uint64_t dropped_seen_ = 0;
};

}  // namespace tgw::dds
