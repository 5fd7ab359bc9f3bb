// One radio channel shared by a fleet (issue 21, part 3): how much of it each robot's gateway may budget for.
// Pure: the base camp feeds it each robot's demand and the channel's measured capacity, and hands out the grants.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "base/clock.hpp"
#include "base/time.hpp"

namespace tgw::core {

/// What one robot needs of the channel at one urgency: the bits per second its samples with this TTL need, to leave
/// before their deadlines (what arrives per second, and what waits spread over the TTL).
struct UrgencyDemand {
    base::Duration ttl{};
    double bps = 0;
};

/// Each robot's demands, by robot; each robot's grant in bit/s; and the least each robot needs (RobotFloors).
using ChannelDemands = std::map<std::string, std::vector<UrgencyDemand>>;
using ChannelGrants = std::map<std::string, double>;
using RobotFloors = std::map<std::string, double>;

/// Splits `capacity_bps` among the robots of `demands`, following urgency across robots, as the gateway's scheduler
/// does within one robot:
/// 1. every robot gets `floor_bps`, or its own floor in `floors` where that is higher, which counts against its
///    most urgent demands: its status and discovery, and its most urgent sample, always have room (floors that
///    add up to more than the channel are cut in proportion);
/// 2. then the demands in order of TTL, shortest first, each urgency across all robots at once: met in full while
///    the channel lasts, and the first that does not fit shared in proportion to what each robot asked;
/// 3. what is left after every demand, in equal parts (a gateway's own sensor still caps what it sends).
/// The grants never add up to more than the channel.
ChannelGrants split_channel(double capacity_bps, const ChannelDemands& demands, double floor_bps,
                            const RobotFloors& floors = {});

/// The baseline that split_channel() improves on: the channel in equal parts, whatever each robot needs.
ChannelGrants equal_shares(double capacity_bps, const ChannelDemands& demands);

/// The base camp's view of the fleet over time: the latest demand of each robot and the channel's capacity, and
/// the grants they give. A robot not heard from for Config::stale_after, or what its report said (stopped,
/// restarted, out of range), has no share until it reports again.
class ChannelShares {
  public:
    struct Config {
        base::Duration stale_after = std::chrono::seconds(5);
        double floor_bps = 0;  ///< see split_channel()
    };

    ChannelShares(Config config, const base::Clock& clock);

    /// What the channel delivers now, in bit/s (the base camp's measure of it: receiver reports).
    void set_capacity(double bps);
    /// `robot`'s demand now, and the least it needs (`floor_bps`, above Config::floor_bps: see split_channel());
    /// it holds for `stale_after` (Config::stale_after when nullopt).
    void report(const std::string& robot, std::vector<UrgencyDemand> demand,
                std::optional<base::Duration> stale_after = std::nullopt, double floor_bps = 0);
    /// What the base camp itself sends `robot` on the channel now (its commands, where one channel carries both
    /// directions), at the urgency `traffic.ttl`: it leaves whatever the grants say, so it is added to the robot's
    /// floor and to its demand, and replaces what was set before (0 bit/s: nothing). It keeps no share of a robot
    /// not heard from.
    void set_camp_traffic(const std::string& robot, UrgencyDemand traffic);
    /// Forgets `robot` at once (its gateway restarted under another name): no share until it reports again.
    void forget(const std::string& robot);
    /// The grants of the robots heard from within stale_after; none before set_capacity().
    ChannelGrants grants();

  private:
    struct Heard {
        std::vector<UrgencyDemand> demand;
        double floor_bps = 0;
        base::SteadyTime until;  ///< when it goes stale
    };

    const Config config_;
    const base::Clock& clock_;
    double capacity_bps_ = -1;  ///< negative: not measured yet
    std::map<std::string, Heard> robots_;
    std::map<std::string, UrgencyDemand> camp_traffic_;
};

}  // namespace tgw::core
