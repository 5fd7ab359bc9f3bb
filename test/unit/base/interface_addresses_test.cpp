#include "base/interface_addresses.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace tgw::base {
namespace {

TEST(InterfaceAddressesTest, ListsLoopbackByName) {
    const auto addresses = interface_addresses();
    ASSERT_TRUE(addresses.has_value());
    EXPECT_TRUE(std::any_of(addresses->begin(), addresses->end(), [](const InterfaceAddress& each) {
        return each.interface == "lo" && each.address == "127.0.0.1";
    }));
}

TEST(InterfaceAddressesTest, TheRouteToALoopbackPeerLeavesFromLoopback) {
    EXPECT_EQ(route_source_address("127.0.0.1"), "127.0.0.1");
    EXPECT_EQ(route_source_address("127.3.2.1"), "127.0.0.1");
}

TEST(InterfaceAddressesTest, ANameIsNoPeerToRouteTo) {
    EXPECT_EQ(route_source_address("basecamp.local"), std::nullopt);
    EXPECT_EQ(route_source_address(""), std::nullopt);
}

TEST(InterfaceAddressesTest, LooksHostNamesUpAndAnAddressIsItsOwn) {
    EXPECT_EQ(lookup_ipv4("localhost"), "127.0.0.1");
    EXPECT_EQ(lookup_ipv4("10.77.0.2"), "10.77.0.2");
    EXPECT_EQ(lookup_ipv4("tgw-no-such-host.invalid"), std::nullopt);  // RFC 6761: never resolves
}

TEST(InterfaceAddressesTest, TellsHostNamesFromOtherText) {
    EXPECT_TRUE(is_host_name("basecamp"));
    EXPECT_TRUE(is_host_name("basecamp-2.local"));
    EXPECT_FALSE(is_host_name(""));
    EXPECT_FALSE(is_host_name("-basecamp"));
    EXPECT_FALSE(is_host_name("base camp"));
    EXPECT_FALSE(is_host_name("camp/1"));
}

TEST(InterfaceAddressesTest, TellsLoopbackAddresses) {
    EXPECT_TRUE(is_loopback_ipv4("127.0.0.1"));
    EXPECT_TRUE(is_loopback_ipv4("127.255.0.9"));
    EXPECT_FALSE(is_loopback_ipv4("10.77.0.1"));
    EXPECT_FALSE(is_loopback_ipv4("lo"));
    EXPECT_TRUE(is_ipv4("10.77.0.1"));
    EXPECT_FALSE(is_ipv4("10.77.0"));
}

}  // namespace
}  // namespace tgw::base
