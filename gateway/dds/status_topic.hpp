#pragma once

namespace tgw::dds {

/// The WAN topic on which each gateway says what it is doing (idl/GatewayStatus.idl), keyed by its WAN
/// participant's GUID prefix.
inline constexpr const char* STATUS_TOPIC = "tgw/status";

/// The largest share of the sensed rate the status may take: it comes less often on a slow link.
inline constexpr double STATUS_RATE_SHARE = 0.02;

}  // namespace tgw::dds
