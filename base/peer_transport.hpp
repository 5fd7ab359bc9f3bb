#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include "base/discovery_server.hpp"
#include "base/receive_buffer.hpp"
#include "base/rtps_ports.hpp"

namespace tgw::base {

/// How a participant reaches the other end of the slow link. Empty fields keep Fast DDS defaults.
struct PeerTransport {
    std::vector<std::string> peers;  ///< IPv4 addresses of the other end; non-empty means unicast only
    std::string interface;           ///< interface name or IPv4 address the participant is bound to
    /// ADDR:PORT of a Fast DDS Discovery Server (base/discovery_server.hpp): discovery through it alone, UDP
    /// unicast only; excludes `peers`.
    std::string discovery_server;
    /// SO_RCVBUF of the UDP sockets: a camp tool takes whole frames off the link, and behind by three 64 KiB
    /// samples the system's default buffer would drop the next (base/receive_buffer.hpp).
    std::uint32_t receive_buffer_bytes = DEFAULT_RECEIVE_BUFFER_BYTES;
    /// A base-camp tool subscribes to whatever it discovers, so it hears of every endpoint.
    DiscoveryRole discovery_role = DiscoveryRole::super_client;
    std::string peers_flag = "--peer";
    std::string interface_flag = "--interface";
    std::string discovery_server_flag = "--discovery-server";
};

/// A UDPv4 locator of `address` (dotted) and `port`; port 0 lets Fast DDS fill in the well-known one.
eprosima::fastrtps::rtps::Locator_t udp_locator(const std::string& address, std::uint32_t port = 0);

/// The IPv4 address of `name_or_addr`: an address as given, or the first IPv4 address of the interface so
/// named. Throws ConfigError naming `flag` when it is neither.
std::string resolve_ipv4(const std::string& name_or_addr, const std::string& flag);

/// `transport.peers` as IPv4 addresses: an address as given, a host name as the resolver has it now (lookup_ipv4:
/// /etc/hosts, DNS, mDNS as nsswitch.conf says). Throws ConfigError naming the flag for a peer that is neither, or
/// a name that does not resolve. May block for as long as the resolver takes.
std::vector<std::string> resolve_peers(const PeerTransport& transport);

/// A peer on this host (a loopback address) gets the announcements at the ports of this many participants of
/// the domain: the gateway, a relay and the tools run beside them share the host, and take participant ids in
/// the order they start. A datagram to loopback costs the radio nothing.
constexpr int SAME_HOST_PEER_PARTICIPANTS = 8;

/// Configures `qos` for the link to the other end of `domain`, its UDP sockets with `transport.receive_buffer_bytes`
/// whatever else is set. With peers (resolve_peers): UDPv4 only (no shared
/// memory, no multicast), SPDP to a remote peer's first participant port only (to a loopback peer's first
/// SAME_HOST_PEER_PARTICIPANTS), longer announcement period. With a discovery server: the same, but discovery
/// through the server. With an interface: every UDP socket bound to its address. Throws ConfigError on a bad
/// address.
void apply_peer_transport(eprosima::fastdds::dds::DomainParticipantQos& qos, const PeerTransport& transport,
                          int domain);

}  // namespace tgw::base
