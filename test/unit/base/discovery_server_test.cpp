#include "base/discovery_server.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include <fastdds/rtps/attributes/ServerAttributes.h>
#include <fastrtps/utils/IPLocator.h>

#include "base/config_error.hpp"

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

}  // namespace
}  // namespace tgw::base
