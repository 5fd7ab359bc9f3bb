// The camp's WAN participant gets the receive buffer it asks for (base::PeerTransport::receive_buffer_bytes), as the
// kernel reports it on the socket Fast DDS listens on: with the system's default, 208 KiB, three 64 KiB samples
// filled it and the fourth was lost (docs/performance.md).
#include <gtest/gtest.h>

#include <dirent.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>

#include "base/peer_transport.hpp"
#include "base/receive_buffer.hpp"
#include "base/rtps_ports.hpp"
#include "test/integration/dds_test_support.hpp"

namespace tgw::test {
namespace {

constexpr std::uint32_t ASKED_BYTES = 1u << 20;
constexpr int PARTICIPANT_ID = 62;

/// SO_RCVBUF of this process's UDP socket bound to `port`, as the kernel reports it; none without such a socket.
std::optional<int> receive_buffer_of_socket_at(std::uint16_t port) {
    DIR* dir = ::opendir("/proc/self/fd");
    if (dir == nullptr)
        return std::nullopt;
    std::optional<int> found;
    while (const dirent* entry = ::readdir(dir)) {
        const int fd = std::atoi(entry->d_name);
        int type = 0;
        socklen_t length = sizeof(type);
        if (fd <= 0 || ::getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &length) != 0 || type != SOCK_DGRAM)
            continue;
        sockaddr_in address{};
        socklen_t address_length = sizeof(address);
        if (::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &address_length) != 0 ||
            address.sin_family != AF_INET || ntohs(address.sin_port) != port)
            continue;
        int bytes = 0;
        length = sizeof(bytes);
        if (::getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &bytes, &length) == 0)
            found = bytes;
    }
    ::closedir(dir);
    return found;
}

/// What the kernel reports for ASKED_BYTES: twice what it grants (its bookkeeping), the grant capped by rmem_max.
int expected_report() {
    const std::uint64_t cap = base::kernel_receive_buffer_cap().value_or(ASKED_BYTES);
    return 2 * static_cast<int>(std::min<std::uint64_t>(ASKED_BYTES, cap));
}

/// The socket of the participant made with `transport` at its discovery port, SO_RCVBUF as the kernel says.
std::optional<int> receive_buffer_with(base::PeerTransport transport) {
    const TestDomains domains = TestDomains::for_this_process();
    transport.receive_buffer_bytes = ASKED_BYTES;
    fdds::DomainParticipantQos qos;
    qos.wire_protocol().participant_id = PARTICIPANT_ID;
    base::apply_peer_transport(qos, transport, domains.wan);
    TestParticipant participant(domains.wan, qos);
    if (!participant.ok())
        return std::nullopt;
    return receive_buffer_of_socket_at(
        static_cast<std::uint16_t>(base::metatraffic_unicast_port(domains.wan, PARTICIPANT_ID)));
}

TEST(ReceiveBufferTest, AToolWithPeersGetsTheBufferItAsksFor) {
    base::PeerTransport transport;
    transport.peers = {"127.0.0.1"};
    EXPECT_EQ(receive_buffer_with(transport), expected_report());
}

TEST(ReceiveBufferTest, AToolWithFastDdsTransportsGetsTheBufferItAsksFor) {
    EXPECT_EQ(receive_buffer_with(base::PeerTransport{}), expected_report());
}

TEST(ReceiveBufferTest, ACampToolAsksForMoreThanTheSystemsDefault) {
    // net.core.rmem_default is 212,992 bytes on Debian: three 64 KiB samples.
    EXPECT_GE(base::PeerTransport{}.receive_buffer_bytes, 16u * 65536u);
}

}  // namespace
}  // namespace tgw::test
