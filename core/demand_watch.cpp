#include "core/demand_watch.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

namespace tgw::core {

bool demand_changed(const std::vector<UrgencyDemand>& told, const std::vector<UrgencyDemand>& now, double fraction,
                    double floor_bps) {
    std::map<base::Duration, std::pair<double, double>> by_ttl;  // told, now
    for (const UrgencyDemand& d : told)
        by_ttl[d.ttl].first += d.bps;
    for (const UrgencyDemand& d : now)
        by_ttl[d.ttl].second += d.bps;
    return std::any_of(by_ttl.begin(), by_ttl.end(), [&](const auto& entry) {
        const auto& [was, is] = entry.second;
        return std::abs(is - was) > std::max(fraction * was, floor_bps);
    });
}

bool more_urgent_than_told(const std::vector<UrgencyDemand>& told, const std::vector<UrgencyDemand>& now,
                           double floor_bps) {
    const auto above_floor = [floor_bps](const UrgencyDemand& d) { return d.bps > floor_bps; };
    const auto most_urgent = [&](const std::vector<UrgencyDemand>& demand) -> std::optional<base::Duration> {
        std::optional<base::Duration> ttl;
        for (const UrgencyDemand& d : demand) {
            if (above_floor(d) && (!ttl || d.ttl < *ttl))
                ttl = d.ttl;
        }
        return ttl;
    };
    const std::optional<base::Duration> is = most_urgent(now);
    const std::optional<base::Duration> was = most_urgent(told);
    return is && (!was || *is < *was);
}

DemandWatch::DemandWatch(Config config, WireModel wire) : config_(config), wire_(wire) {}

bool DemandWatch::changed(base::SteadyTime now, const std::vector<TopicLoad>& loads, double rate_bps) {
    recent_.emplace_back(now, loads);
    // Keep one snapshot at or before the window's start, so that the demand spans the whole window.
    while (recent_.size() > 2 && recent_[1].first <= now - config_.window)
        recent_.pop_front();
    if (pending_)
        return false;
    if (!last_sent_)
        return true;
    if (recent_.size() < 2)
        return false;
    const std::vector<UrgencyDemand> demand =
        urgency_demand(recent_.front().second, loads, now - recent_.front().first, wire_);
    // The one status the statuses' share must not hold back: without it the grant stays too small for the very
    // samples it is about, and they expire while the next status waits for its spacing.
    if (more_urgent_than_told(told_, demand, config_.floor_bps))
        return true;
    if (last_left_ && rate_bps > 0 &&
        now - last_left_->first < base::from_seconds(last_left_->second / (config_.rate_share * rate_bps)))
        return false;
    return demand_changed(told_, demand, config_.fraction, config_.floor_bps);
}

void DemandWatch::sent(base::SteadyTime at, std::vector<TopicLoad> loads, double wire_bits) {
    pending_ = Snapshot{at, std::move(loads)};
    pending_bits_ = wire_bits;
}

void DemandWatch::delivered(bool left, base::SteadyTime seen_at) {
    if (!pending_)
        return;
    if (left) {
        last_left_.emplace(seen_at, pending_bits_);
        // As the base camp works it out: from the status before, or for the first one what waits (ChannelGrantor:
        // its counts gathered over an unknown time); the span only has to be positive then.
        const auto& [at, loads] = *pending_;
        told_ = last_sent_ ? urgency_demand(last_sent_->second, loads, at - last_sent_->first, wire_)
                           : urgency_demand(loads, loads, std::chrono::seconds(1), wire_);
        last_sent_ = std::move(pending_);
    }
    pending_.reset();
}

}  // namespace tgw::core
