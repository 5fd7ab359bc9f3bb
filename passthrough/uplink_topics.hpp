// telemetry-gateway --uplink: the topics the base camp may publish into the robot domain, and nothing else.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/time.hpp"

namespace tgw::passthrough {

/// The uplink's allow-list: robot topic names as the robot's programs subscribe to them (rt/cmd_vel), and the
/// names the base camp publishes them under on the WAN (rt/NAME/cmd_vel with --robot-name NAME,
/// base::namespaced_topic). Exact names, no globs: what may command a robot is spelled out.
class UplinkTopics {
  public:
    /// Throws base::ConfigError naming --uplink when a topic is empty or holds a glob character.
    UplinkTopics(const std::vector<std::string>& robot_topics, const std::string& robot_name);

    /// The robot topic `wan_topic` is the WAN name of, or nullopt when it is not on the list.
    std::optional<std::string> robot_topic(std::string_view wan_topic) const;
    bool empty() const { return routes_.empty(); }
    /// Every listed topic's WAN name, in the order listed.
    std::vector<std::string> wan_topics() const;

  private:
    struct Route {
        std::string wan;
        std::string robot;
    };
    std::vector<Route> routes_;
};

/// Whether a command stamped `source` at the base camp, with time to live `ttl`, is still worth delivering at
/// `now` (both wall clocks): a stale velocity command is worse than none, so one at or past its deadline is not.
bool uplink_expired(base::WallTime source, base::Duration ttl, base::WallTime now);

}  // namespace tgw::passthrough
