// The RTPS well-known ports (RTPS 2.x, 9.6.1.1), without DDS.
#pragma once

#include <cstdint>

namespace tgw::base {

/// The default port mapping's constants (PB, DG, PG, d1).
constexpr int RTPS_PORT_BASE = 7400;
constexpr int RTPS_DOMAIN_GAIN = 250;
constexpr int RTPS_PARTICIPANT_GAIN = 2;
constexpr int RTPS_OFFSET_METATRAFFIC_UNICAST = 10;

/// The metatraffic unicast port of participant `participant_id` in `domain`; past 65535 for a domain or index
/// too large (callers check), so it is returned wide.
constexpr int metatraffic_unicast_port_wide(int domain, int participant_id) {
    return RTPS_PORT_BASE + RTPS_DOMAIN_GAIN * domain + RTPS_OFFSET_METATRAFFIC_UNICAST +
           RTPS_PARTICIPANT_GAIN * participant_id;
}

/// The RTPS well-known metatraffic unicast port of participant `participant_id` in `domain`.
constexpr std::uint16_t metatraffic_unicast_port(int domain, int participant_id) {
    return static_cast<std::uint16_t>(metatraffic_unicast_port_wide(domain, participant_id));
}

}  // namespace tgw::base
