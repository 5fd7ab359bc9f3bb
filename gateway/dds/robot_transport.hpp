#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/receive_buffer.hpp"

namespace tgw::dds {

/// How the gateway's robot participant listens (--robot-interface, --robot-shm, --robot-receive-buffer).
struct RobotTransport {
    /// IPv4 addresses or interface names the UDP transport uses (the Gateway resolves names). On loopback the
    /// participant announces itself to every participant index's discovery port and answers a process's other
    /// addresses on 127.0.0.1 (base::apply_host_transport), so it finds every robot process with UDP, whoever
    /// runs it.
    std::vector<std::string> interfaces{"127.0.0.1"};
    /// Fast DDS shared memory too, for discovery and samples: for publishers that use nothing else. Off by
    /// default: a Fast DDS process prefers shared memory to reach a participant that offers it, and Fast DDS 2.9
    /// makes its shared-memory files writable by their owner alone, so a process of another user would find the
    /// gateway and never reach it. With it on, a publisher with both transports sends every sample both ways.
    bool shm = false;
    /// SO_RCVBUF of the UDP sockets: room for a burst while the forwarding thread is busy.
    std::uint32_t receive_buffer_bytes = base::DEFAULT_RECEIVE_BUFFER_BYTES;
};

}  // namespace tgw::dds
