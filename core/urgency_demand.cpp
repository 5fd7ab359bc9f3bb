#include "core/urgency_demand.hpp"

#include <algorithm>
#include <map>

namespace tgw::core {

namespace {

const TopicLoad* find(const std::vector<TopicLoad>& topics, const std::string& name) {
    for (const TopicLoad& t : topics) {
        if (t.name == name)
            return &t;
    }
    return nullptr;
}

/// The mean payload of `t`'s samples waiting now; 0 when none waits.
std::size_t waiting_payload_bytes_per_sample(const TopicLoad& t) {
    return static_cast<std::size_t>(t.queued_samples > 0 ? t.queued_bytes / t.queued_samples : 0);
}

/// The wire size of one of `t`'s samples waiting now, by their mean payload; headers alone when none waits.
double waiting_wire_bytes_per_sample(const TopicLoad& t, const WireModel& wire) {
    return static_cast<double>(wire.wire_bytes(waiting_payload_bytes_per_sample(t)));
}

/// The mean wire size of one of `t`'s samples: of those forwarded, else of those waiting.
double wire_bytes_per_sample(const TopicLoad& t, const WireModel& wire) {
    if (t.forwarded > 0)
        return static_cast<double>(t.forwarded_wire_bytes) / static_cast<double>(t.forwarded);
    return waiting_wire_bytes_per_sample(t, wire);
}

/// The mean payload of one of `t`'s samples: of those forwarded, else of those waiting (0 when none).
std::size_t payload_bytes_per_sample(const TopicLoad& t) {
    if (t.forwarded > 0)
        return static_cast<std::size_t>(t.forwarded_payload_bytes / t.forwarded);
    return waiting_payload_bytes_per_sample(t);
}

/// The part of its rate a gateway budgets, as its status says it; anything not in (0, 1] counts as all of it.
double usable_fraction(double budget_fraction) {
    return budget_fraction > 0 && budget_fraction <= 1 ? budget_fraction : 1.0;
}

}  // namespace

std::vector<UrgencyDemand> urgency_demand(const std::vector<TopicLoad>& before, const std::vector<TopicLoad>& now,
                                          base::Duration elapsed, const WireModel& wire) {
    if (elapsed <= base::Duration::zero())
        return {};
    const double seconds = base::to_seconds(elapsed);
    std::map<base::Duration, double> by_ttl;
    for (const TopicLoad& t : now) {
        const TopicLoad* earlier = find(before, t.name);
        const std::uint64_t since = earlier != nullptr ? earlier->received : 0;
        const double arrived = t.received >= since ? static_cast<double>(t.received - since) : 0.0;
        const double per_sample = wire_bytes_per_sample(t, wire);
        // A topic that began within the window came over its own time, not the window's: a robot's first status,
        // 0.2 s into its publishing, told a tenth of what came, and its share stayed at its floor for 3 s, while
        // its B expired (three robots, grants: B 197 of 200).
        double over = seconds;
        if (since == 0 && t.active_for > base::Duration::zero())
            over = std::min(seconds, std::max(base::to_seconds(t.active_for), base::to_seconds(MIN_ACTIVE)));
        double bytes_per_second = arrived / over * per_sample;
        if (t.queued_samples > 0 && t.ttl > base::Duration::zero()) {
            const double queued_wire = static_cast<double>(t.queued_samples) * waiting_wire_bytes_per_sample(t, wire);
            bytes_per_second += queued_wire / base::to_seconds(t.ttl);
        }
        by_ttl[t.ttl] += 8 * bytes_per_second;
    }
    std::vector<UrgencyDemand> out;
    for (const auto& [ttl, bps] : by_ttl)
        out.push_back(UrgencyDemand{ttl, bps});
    return out;
}

std::vector<UrgencyDemand> grantable_demand(std::vector<UrgencyDemand> demand, double unscheduled_bps,
                                            double budget_fraction) {
    if (demand.empty())
        return demand;
    const double fraction = usable_fraction(budget_fraction);
    demand.front().bps += std::max(0.0, unscheduled_bps);  // shortest TTL first
    for (UrgencyDemand& d : demand)
        d.bps /= fraction;
    return demand;
}

double least_share_bps(const std::vector<TopicLoad>& topics, std::size_t status_payload_bytes,
                       base::Duration status_ttl, const AloneWire& wire, double budget_fraction,
                       double unscheduled_bps) {
    const auto status_wire_bytes = static_cast<double>(wire.wire_bytes(status_payload_bytes, true));
    double bps = status_ttl > base::Duration::zero() ? 8.0 * status_wire_bytes / base::to_seconds(status_ttl) : 0.0;
    const TopicLoad* urgent = nullptr;
    for (const TopicLoad& t : topics) {
        if (t.ttl > base::Duration::zero() && (t.forwarded > 0 || t.queued_samples > 0) &&
            (urgent == nullptr || t.ttl < urgent->ttl))
            urgent = &t;
    }
    if (urgent != nullptr) {
        for (const TopicLoad& t : topics) {  // every topic of that TTL: the largest sample among them
            if (t.ttl == urgent->ttl && (t.forwarded > 0 || t.queued_samples > 0)) {
                const auto sample_wire_bytes = static_cast<double>(wire.wire_bytes(payload_bytes_per_sample(t)));
                bps = std::max(bps, 8.0 * (status_wire_bytes + sample_wire_bytes) / base::to_seconds(t.ttl));
            }
        }
    }
    return (bps + std::max(0.0, unscheduled_bps)) / usable_fraction(budget_fraction);
}

}  // namespace tgw::core
