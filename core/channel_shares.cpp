#include "core/channel_shares.hpp"

#include <algorithm>
#include <utility>

namespace tgw::core {

namespace {

/// One robot's demand at one urgency, still to be granted.
struct Open {
    base::Duration ttl{};
    const std::string* robot = nullptr;
    double bps = 0;
};

/// Takes `bps` off `robot`'s most urgent demands in `open` (its floor pays for them).
void cover_most_urgent(std::vector<Open>& open, const std::string& robot, double bps) {
    for (Open& o : open) {  // sorted by TTL
        if (bps <= 0)
            return;
        if (*o.robot != robot)
            continue;
        const double covered = std::min(o.bps, bps);
        o.bps -= covered;
        bps -= covered;
    }
}

}  // namespace

ChannelGrants split_channel(double capacity_bps, const ChannelDemands& demands, double floor_bps,
                            const RobotFloors& floors) {
    ChannelGrants grants;
    if (demands.empty())
        return grants;
    double left = std::max(0.0, capacity_bps);
    const auto robots = static_cast<double>(demands.size());
    double all_floors = 0;
    for (const auto& [robot, classes] : demands) {
        const auto own = floors.find(robot);
        grants[robot] = std::max({0.0, floor_bps, own != floors.end() ? own->second : 0.0});
        all_floors += grants[robot];
    }
    if (all_floors > left) {
        for (auto& [robot, bps] : grants)
            bps *= left / all_floors;
        all_floors = left;
    }

    std::vector<Open> open;
    for (const auto& [robot, classes] : demands) {
        for (const UrgencyDemand& d : classes) {
            if (d.bps > 0)
                open.push_back(Open{d.ttl, &robot, d.bps});
        }
    }
    left -= all_floors;
    std::stable_sort(open.begin(), open.end(), [](const Open& a, const Open& b) { return a.ttl < b.ttl; });
    for (const auto& [robot, bps] : grants)
        cover_most_urgent(open, robot, bps);

    // One urgency at a time, across robots.
    for (auto first = open.begin(); first != open.end() && left > 0;) {
        const auto last = std::find_if(first, open.end(), [&](const Open& o) { return o.ttl != first->ttl; });
        double asked = 0;
        for (auto it = first; it != last; ++it)
            asked += it->bps;
        const double part = asked <= left ? 1.0 : left / asked;
        for (auto it = first; it != last; ++it)
            grants[*it->robot] += it->bps * part;
        left -= std::min(asked, left);
        first = last;
    }
    if (left > 0) {
        for (auto& [robot, bps] : grants)
            bps += left / robots;
    }
    return grants;
}

ChannelGrants equal_shares(double capacity_bps, const ChannelDemands& demands) {
    ChannelGrants grants;
    for (const auto& [robot, classes] : demands)
        grants[robot] = std::max(0.0, capacity_bps) / static_cast<double>(demands.size());
    return grants;
}

ChannelShares::ChannelShares(Config config, const base::Clock& clock) : config_(config), clock_(clock) {}

void ChannelShares::set_capacity(double bps) {
    capacity_bps_ = bps;
}

void ChannelShares::report(const std::string& robot, std::vector<UrgencyDemand> demand,
                           std::optional<base::Duration> stale_after, double floor_bps) {
    robots_[robot] = Heard{std::move(demand), floor_bps, clock_.now() + stale_after.value_or(config_.stale_after)};
}

void ChannelShares::set_camp_traffic(const std::string& robot, UrgencyDemand traffic) {
    if (traffic.bps > 0)
        camp_traffic_[robot] = traffic;
    else
        camp_traffic_.erase(robot);
}

void ChannelShares::forget(const std::string& robot) {
    robots_.erase(robot);
    camp_traffic_.erase(robot);
}

ChannelGrants ChannelShares::grants() {
    const base::SteadyTime now = clock_.now();
    for (auto it = robots_.begin(); it != robots_.end();) {
        it = now > it->second.until ? robots_.erase(it) : std::next(it);
    }
    if (capacity_bps_ < 0)
        return {};
    ChannelDemands demands;
    RobotFloors floors;
    for (const auto& [robot, heard] : robots_) {
        demands[robot] = heard.demand;
        floors[robot] = heard.floor_bps;
        if (const auto camp = camp_traffic_.find(robot); camp != camp_traffic_.end()) {
            demands[robot].push_back(camp->second);
            floors[robot] = std::max(heard.floor_bps, config_.floor_bps) + camp->second.bps;
        }
    }
    return split_channel(capacity_bps_, demands, config_.floor_bps, floors);
}

}  // namespace tgw::core
