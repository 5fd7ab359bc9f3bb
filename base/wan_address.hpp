#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/peer_transport.hpp"

namespace tgw::base {

/// A base-camp participant the WAN participant announces itself to: its metatraffic unicast locator.
struct WanPeer {
    std::string address;  ///< dotted IPv4; empty while `host` does not resolve
    /// The host name given instead of an address (a camp laptop on DHCP, "basecamp.local"): resolved at start and
    /// again every few seconds, the WAN participant made anew when its address comes or changes.
    std::string host;
    std::uint16_t port = 0;
    /// The port was given: announce to it alone. Otherwise `port` is participant 0's and the gateway announces
    /// to the first few participants' ports (peer_ports).
    bool exact_port = false;

    bool operator==(const WanPeer& other) const {
        return address == other.address && host == other.host && port == other.port && exact_port == other.exact_port;
    }
    bool operator!=(const WanPeer& other) const { return !(*this == other); }
};

/// Parses --wan-peer "ADDR", "HOST", "ADDR:PORT" or "HOST:PORT" (IPv4, or a host name left unresolved: `host` set,
/// `address` empty). Without a port, `port` is participant 0's in `domain`. Throws base::ConfigError naming the flag
/// and value.
WanPeer parse_wan_peer(const std::string& text, int domain);

/// The metatraffic ports the WAN participant announces itself to on `peer`: the one given, or those of
/// participants 0 .. participants-1 of `domain` on that host (several base-camp programs, each its own
/// participant; one that announces itself to the robot is found whatever its index).
std::vector<std::uint16_t> peer_ports(const WanPeer& peer, int domain, int participants);

/// --wan-interface (or another `flag`) as the IPv4 address to bind to: an address is returned as is (after
/// checking its syntax), an interface name is looked up. Throws base::ConfigError naming the flag when neither
/// works.
std::string resolve_interface_address(const std::string& name_or_address, const std::string& flag = "--wan-interface");

/// `given` (parse_wan_peer's) with each host name resolved now (base::lookup_ipv4; `address` empty when it does
/// not resolve). May block for as long as the resolver takes.
std::vector<WanPeer> resolve_peer_names(std::vector<WanPeer> given);

/// What the WAN participant announces itself to for `peers`: each resolved peer at its peer_ports, exact ports.
std::vector<WanPeer> announcement_peers(const std::vector<WanPeer>& peers, int domain, int participants);

/// Where the WAN participant waits for an interface with no IPv4 address yet (a radio not associated, DHCP not
/// done): it is bound to loopback, announcing nothing anyone far away can use, until the interface has an address
/// and the participant is made anew on it (Gateway::rebind_wan).
inline const std::string ADDRESS_TO_COME = "127.0.0.1";

/// The IPv4 address the WAN participant starts on for --wan-interface: an address as given (after checking its
/// syntax); an interface's first one, or ADDRESS_TO_COME while it has none (or is not there yet). Throws
/// base::ConfigError naming the flag when the text is no valid name.
std::string initial_wan_address(const std::string& name_or_address);

/// --wan-interface as an interface name: a name is returned as is, an address is looked up. Throws
/// base::ConfigError naming the flag when no interface has the address.
std::string resolve_interface_name(const std::string& name_or_address);

}  // namespace tgw::base
