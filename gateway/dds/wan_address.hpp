#pragma once

#include <cstdint>
#include <string>

namespace tgw::dds {

/// A base-camp participant the WAN participant announces itself to: its metatraffic unicast locator.
struct WanPeer {
    std::string address;  ///< dotted IPv4
    std::uint16_t port = 0;
};

/// The RTPS well-known metatraffic unicast port of participant `participant_id` in `domain` (RTPS 9.6.1.1).
std::uint16_t metatraffic_unicast_port(int domain, int participant_id);

/// Parses --wan-peer "ADDR" or "ADDR:PORT" (IPv4). Without a port, the peer's exact port is taken to be that
/// of participant 0 in `domain`, so discovery does not go to every possible participant port. Throws
/// core::ConfigError naming the flag and value.
WanPeer parse_wan_peer(const std::string& text, int domain);

/// --wan-interface (or another `flag`) as the IPv4 address to bind to: an address is returned as is (after
/// checking its syntax), an interface name is looked up. Throws core::ConfigError naming the flag when neither
/// works.
std::string resolve_interface_address(const std::string& name_or_address, const std::string& flag = "--wan-interface");

/// --wan-interface as an interface name: a name is returned as is, an address is looked up. Throws
/// core::ConfigError naming the flag when no interface has the address.
std::string resolve_interface_name(const std::string& name_or_address);

}  // namespace tgw::dds
