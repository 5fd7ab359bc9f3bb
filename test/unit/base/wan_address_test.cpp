#include "base/wan_address.hpp"

#include <gtest/gtest.h>

#include "base/config_error.hpp"

namespace tgw::base {
namespace {

using namespace std::chrono_literals;

TEST(WanAddressTest, PeerWithoutPortGetsParticipantZerosMetatrafficPort) {
    const WanPeer sut = parse_wan_peer("192.0.2.7", 1);
    EXPECT_EQ(sut.address, "192.0.2.7");
    EXPECT_EQ(sut.port, 7660);  // 7400 + 250 * 1 + 10
    EXPECT_FALSE(sut.exact_port);
}

TEST(WanAddressTest, APeerWithoutPortIsAnnouncedToTheFirstParticipantsPorts) {
    EXPECT_EQ(peer_ports(parse_wan_peer("192.0.2.7", 1), 1, 3), (std::vector<std::uint16_t>{7660, 7662, 7664}));
    EXPECT_EQ(peer_ports(parse_wan_peer("192.0.2.7:9000", 1), 1, 3), (std::vector<std::uint16_t>{9000}));
}

TEST(WanAddressTest, PeerWithPortKeepsIt) {
    EXPECT_EQ(parse_wan_peer("10.0.0.1:7412", 0).port, 7412);
}

TEST(WanAddressTest, BadPeersAreConfigErrorsNamingTheFlag) {
    for (const char* bad : {"", "base camp", "-camp", "camp/1", "10.0.0.1:", "10.0.0.1:70000", "10.0.0.1:x"}) {
        try {
            parse_wan_peer(bad, 1);
            ADD_FAILURE() << bad;
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("--wan-peer"), std::string::npos);
        }
    }
}

TEST(WanAddressTest, APeerMayBeAHostNameLookedUpLater) {
    const WanPeer named = parse_wan_peer("basecamp.local:7412", 0);
    EXPECT_EQ(named.host, "basecamp.local");
    EXPECT_EQ(named.address, "");
    EXPECT_EQ(named.port, 7412);
    const auto resolved =
        resolve_peer_names({parse_wan_peer("localhost", 1), parse_wan_peer("tgw-no-such-host.invalid", 1)});
    EXPECT_EQ(resolved[0].address, "127.0.0.1");
    EXPECT_EQ(resolved[1].address, "");  // not yet: it is looked up again later
    // Only what resolved is announced to, at the first participants' ports.
    const auto announced = announcement_peers(resolved, 1, 2);
    ASSERT_EQ(announced.size(), 2u);
    EXPECT_EQ(announced[0].address, "127.0.0.1");
    EXPECT_EQ(announced[0].port, 7660);
    EXPECT_EQ(announced[1].port, 7662);
    EXPECT_TRUE(announced[1].exact_port);
}

TEST(WanAddressTest, InterfaceNameResolvesToItsAddress) {
    EXPECT_EQ(resolve_interface_address("lo"), "127.0.0.1");
    EXPECT_EQ(resolve_interface_address("127.0.0.1"), "127.0.0.1");
    EXPECT_THROW(resolve_interface_address("no-such-if0"), ConfigError);
}

TEST(WanAddressTest, ResolvesAnInterfaceNameFromItsAddress) {
    EXPECT_EQ(resolve_interface_name("lo"), "lo");
    EXPECT_EQ(resolve_interface_name("127.0.0.1"), "lo");
    EXPECT_THROW(resolve_interface_name("192.0.2.77"), ConfigError);  // TEST-NET-1: on no interface here
}

}  // namespace
}  // namespace tgw::base
