// What tells the gateway's own WAN topics (tgw/status, tgw/grant, tgw/backfill, ...) from the robot's.
#pragma once

#include <string_view>

namespace tgw::wire {

/// The prefix of every topic the gateway and the base camp's tools publish for themselves.
inline constexpr std::string_view GATEWAY_TOPIC_PREFIX = "tgw/";

/// True for a topic of the gateway's own, which carries none of the robot's telemetry.
inline bool is_gateway_topic(std::string_view topic) {
    return topic.substr(0, GATEWAY_TOPIC_PREFIX.size()) == GATEWAY_TOPIC_PREFIX;
}

}  // namespace tgw::wire
