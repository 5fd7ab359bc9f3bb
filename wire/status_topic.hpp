#pragma once

#include <chrono>

namespace tgw::wire {

/// The WAN topic on which each gateway says what it is doing (idl/GatewayStatus.idl), keyed by its WAN
/// participant's GUID prefix.
inline constexpr const char* STATUS_TOPIC = "tgw/status";

/// A status's TTL in the schedule: it goes before anything less urgent.
inline constexpr std::chrono::seconds STATUS_TTL{1};
/// How long a status lives once sent (its WAN writer's Lifespan): longer than its TTL, because a status that a
/// congested link delayed still tells the base camp what it needs to know (its counts are cumulative, its time
/// the gateway's own); with the Lifespan of its TTL, a fleet's grants starved a robot whose statuses all came a
/// little late.
inline constexpr std::chrono::seconds STATUS_LIFESPAN{5};

/// The largest share of the sensed rate the status may take: it comes less often on a slow link.
inline constexpr double STATUS_RATE_SHARE = 0.02;

/// The least time between statuses of `wire_bits` on the wire at `rate_bps` so that they take at most
/// STATUS_RATE_SHARE of it: what the gateway waits beyond its status period, and what the base camp allows for.
inline std::chrono::duration<double> status_rate_spacing(double wire_bits, double rate_bps) {
    return std::chrono::duration<double>(wire_bits / (STATUS_RATE_SHARE * rate_bps));
}

}  // namespace tgw::wire
