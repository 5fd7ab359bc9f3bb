#pragma once

#include <chrono>

namespace tgw::dds {

/// The WAN topic of the base camp's shares of a fleet's channel (idl/ChannelGrant.idl), keyed by the gateway's WAN
/// participant's GUID prefix: with the receiver reports, what goes from the base camp to the gateway itself.
inline constexpr const char* CHANNEL_GRANT_TOPIC = "tgw/grant";

/// How long a grant holds after it arrives: three of the base camp's grant periods (1 s), so one lost grant
/// changes nothing and a base camp that stops is noticed within seconds.
inline constexpr std::chrono::milliseconds GRANT_VALIDITY{3000};

}  // namespace tgw::dds
