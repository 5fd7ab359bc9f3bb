#pragma once

#include <string>
#include <vector>

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

namespace tgw::base {

/// How a participant reaches the other end of the slow link. Empty fields keep Fast DDS defaults.
struct PeerTransport {
    std::vector<std::string> peers;  ///< IPv4 addresses of the other end; non-empty means unicast only
    std::string interface;           ///< interface name or IPv4 address the participant is bound to
    std::string peers_flag = "--peer";
    std::string interface_flag = "--interface";
};

/// The IPv4 address of `name_or_addr`: an address as given, or the first IPv4 address of the interface so
/// named. Throws ConfigError naming `flag` when it is neither.
std::string resolve_ipv4(const std::string& name_or_addr, const std::string& flag);

/// Configures `qos` for the link. With peers: UDPv4 only (no shared memory, no multicast), SPDP to the
/// peers' first participant port only, longer announcement period. With an interface: every UDP socket
/// bound to its address. Throws ConfigError on a bad address.
void apply_peer_transport(eprosima::fastdds::dds::DomainParticipantQos& qos, const PeerTransport& transport);

}  // namespace tgw::base
