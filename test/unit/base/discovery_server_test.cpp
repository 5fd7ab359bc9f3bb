#include "base/discovery_server.hpp"

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>

#include <sstream>
#include <string>
#include <vector>

#include <fastdds/rtps/attributes/ServerAttributes.h>
#include <fastrtps/utils/IPLocator.h>

#include "base/config_error.hpp"
#include "base/peer_transport.hpp"

namespace tgw::base {
namespace {

using eprosima::fastrtps::rtps::DiscoveryProtocol;

TEST(DiscoveryServerTest, ParsesAddressAndPort) {
    const DiscoveryServerAddress server = parse_discovery_server("10.77.0.2:11811", "--wan-discovery-server");
    EXPECT_EQ(server.address, "10.77.0.2");
    EXPECT_EQ(server.port, 11811);
}

TEST(DiscoveryServerTest, RefusesWhatIsNoIpv4AddressAndPortNamingTheFlag) {
    for (const char* bad :
         {"10.77.0.2", "camp:11811", "10.77.0.2:", "10.77.0.2:0", "10.77.0.2:65536", "10.77.0.2:118x", ":11811"}) {
        try {
            parse_discovery_server(bad, "--discovery-server");
            ADD_FAILURE() << bad << " was taken";
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("--discovery-server '" + std::string(bad) + "'"), std::string::npos)
                << e.what();
        }
    }
}

TEST(DiscoveryServerTest, MakesAClientOfServerZeroAtTheAddress) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    eprosima::fastrtps::rtps::Locator_t peer;
    qos.wire_protocol().builtin.initialPeersList.push_back(peer);
    apply_discovery_client(qos, DiscoveryServerAddress{"10.77.0.2", 11811}, DiscoveryRole::client);
    const auto& discovery = qos.wire_protocol().builtin.discovery_config;
    EXPECT_EQ(discovery.discoveryProtocol, DiscoveryProtocol::CLIENT);
    ASSERT_EQ(discovery.m_DiscoveryServers.size(), 1u);
    const auto& server = discovery.m_DiscoveryServers.front();
    // fastdds discovery -i 0's prefix, which ROS_DISCOVERY_SERVER's first entry names too.
    eprosima::fastrtps::rtps::GuidPrefix_t expected;
    std::istringstream(eprosima::fastdds::rtps::DEFAULT_ROS2_SERVER_GUIDPREFIX) >> expected;
    EXPECT_EQ(server.guidPrefix, expected);
    ASSERT_EQ(server.metatrafficUnicastLocatorList.size(), 1u);
    const auto& locator = *server.metatrafficUnicastLocatorList.begin();
    EXPECT_EQ(eprosima::fastrtps::rtps::IPLocator::ip_to_string(locator), "10.77.0.2");
    EXPECT_EQ(locator.port, 11811u);
    EXPECT_TRUE(qos.wire_protocol().builtin.initialPeersList.empty());
}

TEST(DiscoveryServerTest, ABaseCampToolIsASuperClient) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    apply_discovery_client(qos, DiscoveryServerAddress{"10.77.0.2", 11811}, DiscoveryRole::super_client);
    EXPECT_EQ(qos.wire_protocol().builtin.discovery_config.discoveryProtocol, DiscoveryProtocol::SUPER_CLIENT);
}

std::vector<std::string> whitelist_for_a_server_at(const std::string& bound, const std::string& server) {
    eprosima::fastdds::rtps::UDPv4TransportDescriptor udp;
    udp.interfaceWhiteList.push_back(bound);
    listen_for_a_same_host_server(udp, bound, DiscoveryServerAddress{server, 11811});
    return udp.interfaceWhiteList;
}

TEST(DiscoveryServerTest, ListensOnTheLoopbackForAServerOnItsOwnHost) {
    EXPECT_EQ(whitelist_for_a_server_at("10.77.0.6", "127.0.0.1"),
              (std::vector<std::string>{"10.77.0.6", "127.0.0.1"}));
    EXPECT_EQ(whitelist_for_a_server_at("127.0.0.1", "127.0.0.1"), (std::vector<std::string>{"127.0.0.1"}));
}

TEST(DiscoveryServerTest, ListensOnItsInterfaceAloneForAServerOnAnotherHost) {
    // Another socket on the loopback would send every message a second time, into this host (192.0.2.1: TEST-NET-1,
    // nobody's address).
    EXPECT_EQ(whitelist_for_a_server_at("10.77.1.1", "192.0.2.1"), (std::vector<std::string>{"10.77.1.1"}));
}

TEST(DiscoveryServerTest, ThisHostsAddressesAreItsInterfacesAndTheLoopback) {
    ifaddrs* list = nullptr;
    ASSERT_EQ(getifaddrs(&list), 0);
    std::vector<std::string> own;
    for (const ifaddrs* it = list; it != nullptr; it = it->ifa_next) {
        if (it->ifa_addr == nullptr || it->ifa_addr->sa_family != AF_INET)
            continue;
        char text[INET_ADDRSTRLEN] = {};
        inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(it->ifa_addr)->sin_addr, text, sizeof(text));
        own.emplace_back(text);
    }
    freeifaddrs(list);
    ASSERT_FALSE(own.empty()) << "no IPv4 interface, not even the loopback";
    for (const std::string& address : own)
        EXPECT_TRUE(is_this_hosts_address(address)) << address;
    EXPECT_TRUE(is_this_hosts_address("127.0.0.1"));
    EXPECT_TRUE(is_this_hosts_address("127.3.2.1"));  // all of 127/8 is the loopback's
    EXPECT_FALSE(is_this_hosts_address("192.0.2.1"));
    EXPECT_FALSE(is_this_hosts_address("camp"));
}

}  // namespace
}  // namespace tgw::base
