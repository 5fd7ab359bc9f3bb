// The transports of a participant that serves the DDS processes of its own host, whoever runs them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

namespace tgw::base {

/// Participant indexes a domain has discovery ports for with the RTPS defaults (250 ports a domain, 10 before the
/// first index, 2 each).
constexpr std::uint32_t PARTICIPANT_INDEXES = 120;

/// Where and how a host participant listens (the gateway's robot side, the relay's camp side).
struct HostTransport {
    /// IPv4 addresses the UDP transport uses; empty: every interface.
    std::vector<std::string> addresses;
    /// Fast DDS shared memory too, for processes that use nothing else. Off by default: a Fast DDS process
    /// prefers shared memory to reach a participant that offers it, and Fast DDS 2.9 makes its shared-memory
    /// files writable by their owner alone, so a process of another user finds such a participant and never
    /// reaches it (docs/install.md).
    bool shm = false;
    /// SO_RCVBUF of the UDP sockets; 0: Fast DDS's default.
    std::uint32_t receive_buffer_bytes = 0;
};

/// Configures `qos` (its transports and initial peers, unless the profile it came from named peers) to reach the
/// processes of this host over UDP, whatever user runs them:
/// - UDP on `transport.addresses`; with 127.0.0.1 among them, through LoopbackTransport, so that a process
///   announcing the host's other addresses (Fast DDS's default) is answered on loopback;
/// - announcements to the discovery port of every participant index of `domain` on 127.0.0.1, where Fast DDS
///   and Cyclone DDS processes listen by default (loopback has no multicast), and to the multicast group when
///   an address off loopback may carry it.
void apply_host_transport(eprosima::fastdds::dds::DomainParticipantQos& qos, int domain,
                          const HostTransport& transport);

}  // namespace tgw::base
