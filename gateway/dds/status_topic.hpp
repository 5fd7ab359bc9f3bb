#pragma once

#include <chrono>

namespace tgw::dds {

/// The WAN topic on which each gateway says what it is doing (idl/GatewayStatus.idl), keyed by its WAN
/// participant's GUID prefix.
inline constexpr const char* STATUS_TOPIC = "tgw/status";

/// How long a status lives: its TTL in the schedule and its WAN writer's Lifespan.
inline constexpr std::chrono::seconds STATUS_TTL{1};

/// The largest share of the sensed rate the status may take: it comes less often on a slow link.
inline constexpr double STATUS_RATE_SHARE = 0.02;

}  // namespace tgw::dds
