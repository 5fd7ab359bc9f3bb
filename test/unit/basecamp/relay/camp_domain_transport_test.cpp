#include "basecamp/relay/camp_domain_transport.hpp"

#include <gtest/gtest.h>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>

#include "base/loopback_transport.hpp"

namespace tgw::basecamp {
namespace {

using base::InterfaceAddress;

const std::vector<InterfaceAddress> CAMP_LAPTOP = {
    {"lo", "127.0.0.1"},       {"eth0", "192.168.1.20"},
    {"radio0", "10.77.0.2"},   {"radio0", "10.78.0.2"},  // a second address on the radio: kept off as well
    {"docker0", "172.17.0.1"},
};

TEST(CampDomainTransportTest, EveryAddressButTheRadiosLoopbackIncluded) {
    EXPECT_EQ(camp_addresses_off_the_wan(CAMP_LAPTOP, "10.77.0.2"),
              (std::vector<std::string>{"127.0.0.1", "192.168.1.20", "172.17.0.1"}));
}

TEST(CampDomainTransportTest, AWanOnLoopbackOrOnNoInterfaceKeepsNothingOff) {
    // A robot and its camp on one host (tests, the demo's loopback run): the camp's tools are on loopback too.
    EXPECT_TRUE(camp_addresses_off_the_wan(CAMP_LAPTOP, "127.0.0.1").empty());
    EXPECT_TRUE(camp_addresses_off_the_wan(CAMP_LAPTOP, "10.99.0.1").empty());
}

TEST(CampDomainTransportTest, TheWanAddressIsTheInterfacesOrTheRoutesToThePeer) {
    base::PeerTransport wan;
    EXPECT_EQ(wan_local_address(wan), std::nullopt);
    wan.peers = {"127.0.0.1"};
    EXPECT_EQ(wan_local_address(wan), "127.0.0.1");
    wan.interface = "lo";
    EXPECT_EQ(wan_local_address(wan), "127.0.0.1");
    base::PeerTransport through_a_server;
    through_a_server.discovery_server = "127.0.0.1:11811";
    EXPECT_EQ(wan_local_address(through_a_server), "127.0.0.1");
}

TEST(CampDomainTransportTest, LocalInterfaceStillChooses) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    base::PeerTransport local;
    local.interface = "127.0.0.1";
    base::PeerTransport wan;
    wan.interface = "127.0.0.1";
    EXPECT_EQ(apply_camp_domain_transport(qos, local, wan, 2), (std::vector<std::string>{"127.0.0.1"}));
    const auto loopback =
        std::dynamic_pointer_cast<base::LoopbackTransportDescriptor>(qos.transport().user_transports.front());
    ASSERT_NE(loopback, nullptr);
    const auto* udp =
        dynamic_cast<const eprosima::fastdds::rtps::UDPv4TransportDescriptor*>(loopback->low_level_descriptor.get());
    ASSERT_NE(udp, nullptr);
    EXPECT_EQ(udp->interfaceWhiteList, (std::vector<std::string>{"127.0.0.1"}));
}

TEST(CampDomainTransportTest, WithTheWanOnLoopbackEveryInterfaceOverUdpAlone) {
    // Camp tools of any user reach the relay: no shared memory, which Fast DDS 2.9 keeps to its owner.
    eprosima::fastdds::dds::DomainParticipantQos qos;
    base::PeerTransport wan;
    wan.peers = {"127.0.0.1"};
    EXPECT_TRUE(apply_camp_domain_transport(qos, base::PeerTransport{}, wan, 2).empty());
    EXPECT_FALSE(qos.transport().use_builtin_transports);
    ASSERT_EQ(qos.transport().user_transports.size(), 1u);
    const auto udp = std::dynamic_pointer_cast<eprosima::fastdds::rtps::UDPv4TransportDescriptor>(
        qos.transport().user_transports[0]);
    ASSERT_NE(udp, nullptr);
    EXPECT_TRUE(udp->interfaceWhiteList.empty());
}

TEST(CampDomainTransportTest, TheRelaysLineSaysWhereTheCampsDomainIs) {
    base::PeerTransport wan;
    wan.interface = "127.0.0.1";
    base::PeerTransport local;
    EXPECT_EQ(describe_camp_domain({}, local, wan), "the camp's domain on every interface");
    EXPECT_EQ(describe_camp_domain({"127.0.0.1", "192.168.1.20"}, local, wan),
              "the camp's domain on 127.0.0.1, 192.168.1.20 (kept off the WAN's 127.0.0.1)");
    local.interface = "lo";
    local.interface_flag = "--local-interface";
    EXPECT_EQ(describe_camp_domain({"127.0.0.1"}, local, wan), "the camp's domain on 127.0.0.1 (--local-interface)");
}

}  // namespace
}  // namespace tgw::basecamp
