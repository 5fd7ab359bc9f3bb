#include "passthrough/uplink_topics.hpp"

#include <algorithm>

#include "base/config_error.hpp"
#include "base/robot_namespace.hpp"

namespace tgw::passthrough {

UplinkTopics::UplinkTopics(const std::vector<std::string>& robot_topics, const std::string& robot_name) {
    for (const std::string& topic : robot_topics) {
        if (topic.empty()) {
            throw base::ConfigError("--uplink: empty topic name");
        }
        if (topic.find_first_of("*?[]") != std::string::npos) {
            throw base::ConfigError("--uplink '" + topic +
                                    "': a topic name, not a pattern (what may command the robot is spelled out)");
        }
        const std::string wan = base::namespaced_topic(robot_name, topic);
        const bool listed =
            std::any_of(routes_.begin(), routes_.end(), [&](const Route& route) { return route.robot == topic; });
        if (!listed) {
            routes_.push_back(Route{wan, topic});
        }
    }
}

std::optional<std::string> UplinkTopics::robot_topic(std::string_view wan_topic) const {
    for (const Route& route : routes_) {
        if (route.wan == wan_topic) {
            return route.robot;
        }
    }
    return std::nullopt;
}

std::vector<std::string> UplinkTopics::wan_topics() const {
    std::vector<std::string> out;
    for (const Route& route : routes_) {
        out.push_back(route.wan);
    }
    return out;
}

bool uplink_expired(base::WallTime source, base::Duration ttl, base::WallTime now) {
    return now >= source + std::chrono::duration_cast<base::WallClock::duration>(ttl);
}

}  // namespace tgw::passthrough
