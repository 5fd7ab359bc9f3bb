// What a robot needs of a shared channel, by urgency, from two of its gateway's statuses (tgw/status): the input of
// split_channel() at the base camp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/time.hpp"
#include "core/alone_wire.hpp"
#include "core/channel_shares.hpp"
#include "core/wire_model.hpp"

namespace tgw::core {

/// One topic's counts in a gateway's status (cumulative since the gateway started) and its queue now.
struct TopicLoad {
    std::string name;
    base::Duration ttl{};
    std::uint64_t received = 0;
    std::uint64_t forwarded = 0;
    std::uint64_t forwarded_wire_bytes = 0;
    std::uint64_t queued_samples = 0;
    std::uint64_t queued_bytes = 0;  ///< their serialized payloads
    std::uint64_t forwarded_payload_bytes = 0;
    /// Since its first sample arrived, when the counts were taken; 0 before one did.
    base::Duration active_for{};
};

/// The bit/s each TTL needs, shortest TTL first, from the topics' counts `elapsed` apart: per topic, what arrived
/// per second at its mean size on the wire (what was forwarded, else what waits, as `wire` counts it), plus what
/// waits now spread over its TTL. A topic not in `before` counts from zero; one whose counts went down (a gateway
/// restarted under the same name) counts its queue only. A topic with nothing in `before` that began within
/// `elapsed` counts its arrivals over the time since its first (TopicLoad::active_for), MIN_ACTIVE at least. Empty
/// when `elapsed` is not positive.
/// The least time a new topic's arrivals are counted over: its first two samples, born together, are not a rate.
inline constexpr base::Duration MIN_ACTIVE = std::chrono::milliseconds(500);

std::vector<UrgencyDemand> urgency_demand(const std::vector<TopicLoad>& before, const std::vector<TopicLoad>& now,
                                          base::Duration elapsed, const WireModel& wire);

/// What a gateway must be granted for `demand` to leave in time: its traffic outside the schedule (`unscheduled_bps`:
/// discovery, heartbeats, repairs, which its budget pays before any sample) counted with its most urgent demand, and
/// every demand divided by `budget_fraction`, the part of its rate the gateway budgets (its status: budget over
/// rate). A grant of the demand alone left a robot whose hazards had the whole of it 0.95 of what they needed, less
/// the heartbeats: their queue grew to their TTL. An empty demand stays empty; a fraction not in (0, 1] counts as 1.
std::vector<UrgencyDemand> grantable_demand(std::vector<UrgencyDemand> demand, double unscheduled_bps,
                                            double budget_fraction);

/// The least share a robot needs to keep in touch (split_channel()'s floor for it): room for its status of
/// `status_payload_bytes` within `status_ttl`, and for the status and then one sample of its most urgent topic
/// (shortest TTL; the mean payload of what it forwarded, else of what waits) within that topic's TTL, the larger;
/// each as it goes on the wire by itself (`wire`: in compact mode a bundle of its own each); plus
/// `unscheduled_bps`, the gateway's traffic outside the schedule, which its budget pays first; all divided by
/// `budget_fraction`, the part of its rate the gateway budgets (a fraction not in (0, 1] counts as 1).
/// Below it a status cannot leave, and the base camp never learns the robot's demand: the status alone within its
/// TTL at 95 % of the rate doomed it (454 bytes at 95 % of 3,632 bit/s: 1.05 s), and a status that left the most
/// urgent topic too little time for its own sample was held back for that topic's sake (Scheduler's non-preemptive
/// rule); either way a robot kept that grant for good (ChannelGrantTest, once in CI). Sized as if the two shared a
/// bundle, a compact robot's floor (6,574 bit/s) left its 720-byte status 0.81 s of wire beside A's 0.24: held
/// back, then past its TTL, for 20 s of a fleet run.
double least_share_bps(const std::vector<TopicLoad>& topics, std::size_t status_payload_bytes,
                       base::Duration status_ttl, const AloneWire& wire, double budget_fraction = 1.0,
                       double unscheduled_bps = 0);

}  // namespace tgw::core
