#include "base/quiet_discovery_ports.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>

#include <gtest/gtest.h>

#include "base/rtps_ports.hpp"

namespace tgw::base {
namespace {

// The discovery ports of domains 215 and up lie above Linux's ephemeral range (32768 to 60999): no socket of another
// test takes one by chance. Each test has a domain of its own, as ctest runs them side by side.
constexpr int FIRST_DOMAIN = 220;

/// A UDP socket bound to loopback; closed with the object.
class Socket {
  public:
    Socket() : fd_(socket(AF_INET, SOCK_DGRAM, 0)) {}
    ~Socket() { close(fd_); }
    Socket(const Socket&) = delete;
    Socket& operator=(const Socket&) = delete;

    bool bind_to(std::uint16_t port) const {
        const sockaddr_in local = loopback(port);
        return bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof(local)) == 0;
    }

    /// Sends one datagram to `port` and tells whether the host answered it with an ICMP port unreachable (a
    /// connected UDP socket reports it as ECONNREFUSED).
    bool refused_at(std::uint16_t port) const {
        const sockaddr_in remote = loopback(port);
        if (connect(fd_, reinterpret_cast<const sockaddr*>(&remote), sizeof(remote)) != 0) {
            ADD_FAILURE() << "connect: " << errno;
            return false;
        }
        const char datagram[] = "SPDP";
        if (send(fd_, datagram, sizeof(datagram), 0) < 0) {
            return errno == ECONNREFUSED;
        }
        // Loopback delivers the ICMP before send() returns; a moment more for a slow machine.
        usleep(20000);
        char buffer[16];
        return recv(fd_, buffer, sizeof(buffer), MSG_DONTWAIT) < 0 && errno == ECONNREFUSED;
    }

  private:
    static sockaddr_in loopback(std::uint16_t port) {
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        address.sin_port = htons(port);
        return address;
    }

    int fd_;
};

TEST(QuietDiscoveryPortsTest, AnnouncementsToAHeldPortDrawNoPortUnreachable) {
    constexpr int DOMAIN = FIRST_DOMAIN + 0;
    const std::uint16_t port = metatraffic_unicast_port(DOMAIN, 3);
    EXPECT_TRUE(Socket().refused_at(port)) << "nothing listens there yet: the host answers";
    const QuietDiscoveryPorts quiet("127.0.0.1", DOMAIN);
    EXPECT_FALSE(Socket().refused_at(port));
}

TEST(QuietDiscoveryPortsTest, HoldsTheDiscoveryPortOfEveryParticipantIndexACyclonePeerAnnouncesTo) {
    constexpr int DOMAIN = FIRST_DOMAIN + 1;
    const QuietDiscoveryPorts quiet("127.0.0.1", DOMAIN);
    ASSERT_EQ(quiet.ports().size(), 10u);
    EXPECT_EQ(quiet.ports().front(), metatraffic_unicast_port(DOMAIN, 0));
    EXPECT_EQ(quiet.ports().back(), metatraffic_unicast_port(DOMAIN, 9));
}

TEST(QuietDiscoveryPortsTest, LeavesAPortAParticipantHasToIt) {
    constexpr int DOMAIN = FIRST_DOMAIN + 2;
    Socket participant;
    ASSERT_TRUE(participant.bind_to(metatraffic_unicast_port(DOMAIN, 0)));
    const QuietDiscoveryPorts quiet("127.0.0.1", DOMAIN, 3);
    EXPECT_EQ(quiet.ports(),
              (std::vector<std::uint16_t>{metatraffic_unicast_port(DOMAIN, 1), metatraffic_unicast_port(DOMAIN, 2)}));
}

TEST(QuietDiscoveryPortsTest, GivesThePortsBackWhenItGoes) {
    constexpr int DOMAIN = FIRST_DOMAIN + 3;
    { const QuietDiscoveryPorts quiet("127.0.0.1", DOMAIN, 2); }
    Socket later;
    EXPECT_TRUE(later.bind_to(metatraffic_unicast_port(DOMAIN, 1)));
}

TEST(QuietDiscoveryPortsTest, MovedPortsStayHeldByTheNewOwner) {
    constexpr int DOMAIN = FIRST_DOMAIN + 4;
    QuietDiscoveryPorts held;
    held = QuietDiscoveryPorts("127.0.0.1", DOMAIN, 2);
    EXPECT_EQ(held.ports().size(), 2u);
    Socket other;
    EXPECT_FALSE(other.bind_to(metatraffic_unicast_port(DOMAIN, 0)));
}

TEST(QuietDiscoveryPortsTest, AnAddressThatIsNoneHoldsNothing) {
    constexpr int DOMAIN = FIRST_DOMAIN + 5;
    EXPECT_TRUE(QuietDiscoveryPorts("not-an-address", DOMAIN).ports().empty());
}

TEST(QuietDiscoveryPortsTest, WorthItOnARadiosAddressNotOnLoopback) {
    EXPECT_TRUE(QuietDiscoveryPorts::worth_it("10.77.0.1"));
    EXPECT_FALSE(QuietDiscoveryPorts::worth_it("127.0.0.1"));
    EXPECT_FALSE(QuietDiscoveryPorts::worth_it("127.1.2.3"));
    EXPECT_FALSE(QuietDiscoveryPorts::worth_it(""));
    EXPECT_FALSE(QuietDiscoveryPorts::worth_it("wlan0"));
}

}  // namespace
}  // namespace tgw::base
