#pragma once

#include <array>
#include <chrono>
#include <cstdint>

namespace tgw::wire {

/// The WAN topic of the base camp's shares of a fleet's channel (idl/ChannelGrant.idl), keyed by the gateway's WAN
/// participant's GUID prefix: with the receiver reports, what goes from the base camp to the gateway itself.
inline constexpr const char* CHANNEL_GRANT_TOPIC = "tgw/grant";

/// How long a grant holds after it arrives: three of the base camp's grant periods (1 s), so one lost grant
/// changes nothing and a base camp that stops is noticed within seconds.
inline constexpr std::chrono::milliseconds GRANT_VALIDITY{3000};

/// The key of the newcomers' share (core::GrantView::newcomer_bps): the all-zero prefix, which no participant has.
/// A gateway with no grant of its own budgets for it: what the base camp keeps free for gateways that join.
inline constexpr std::array<std::uint8_t, 12> NEWCOMER_PREFIX{};

}  // namespace tgw::wire
