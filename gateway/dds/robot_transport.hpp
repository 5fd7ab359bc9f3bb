#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tgw::dds {

/// How the gateway's robot participant listens (--robot-interface, --robot-udp-only, --robot-shm-samples,
/// --robot-receive-buffer).
struct RobotTransport {
    static constexpr std::uint32_t DEFAULT_RECEIVE_BUFFER_BYTES = 4u << 20;
    /// Fast DDS refuses a receive buffer smaller than its largest message (65500 B).
    static constexpr std::uint32_t MIN_RECEIVE_BUFFER_BYTES = 1u << 16;
    static constexpr std::uint32_t MAX_RECEIVE_BUFFER_BYTES = 1u << 30;

    /// IPv4 addresses or interface names the UDP transport uses (the Gateway resolves names).
    std::vector<std::string> interfaces{"127.0.0.1"};
    /// Discovery over Fast DDS shared memory too: how the gateway finds a same-host Fast DDS process when UDP
    /// multicast cannot (on loopback it does not work; on a robot whose only other interface is the radio,
    /// nothing else does).
    bool shm = true;
    /// Samples over shared memory too (with `shm`): the readers then offer both transports, and a Fast DDS 2.9
    /// writer sends to every locator of a reader it can reach, so a publisher with both (Fast DDS's default)
    /// sends each sample twice and the gateway receives both copies. Only for publishers with shared memory
    /// alone; the others send their samples to the readers' UDP locators.
    bool shm_samples = false;
    /// SO_RCVBUF of the UDP sockets: room for a burst while the forwarding thread is busy.
    std::uint32_t receive_buffer_bytes = DEFAULT_RECEIVE_BUFFER_BYTES;
};

}  // namespace tgw::dds
