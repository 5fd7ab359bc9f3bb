#include "base/peer_transport.hpp"

#include <gtest/gtest.h>

#include <vector>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include "base/config_error.hpp"

namespace tgw::base {
namespace {

using eprosima::fastrtps::rtps::IPLocator;

struct Peer {
    std::string address;
    std::uint32_t port;
    bool operator==(const Peer& other) const { return address == other.address && port == other.port; }
};

std::vector<Peer> initial_peers(const eprosima::fastdds::dds::DomainParticipantQos& qos) {
    std::vector<Peer> peers;
    for (const auto& locator : qos.wire_protocol().builtin.initialPeersList)
        peers.push_back({IPLocator::ip_to_string(locator), locator.port});
    return peers;
}

TEST(PeerTransportTest, WellKnownPortsFollowRtps) {
    // RTPS 9.6.1.1: 7400 + 250 x domain + 10 + 2 x participant id.
    EXPECT_EQ(metatraffic_unicast_port(0, 0), 7410);
    EXPECT_EQ(metatraffic_unicast_port(1, 2), 7664);
    EXPECT_EQ(metatraffic_unicast_port(203, 0), 58160);
}

TEST(PeerTransportTest, ARemotePeerIsAnnouncedToAtItsFirstParticipantOnly) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    PeerTransport transport;
    transport.peers = {"10.77.0.1"};
    apply_peer_transport(qos, transport, 7);
    // Port 0: Fast DDS's own well-known port, over a range of one participant (the transport's setting).
    EXPECT_EQ(initial_peers(qos), (std::vector<Peer>{{"10.77.0.1", 0}}));
    ASSERT_EQ(qos.transport().user_transports.size(), 1u);
    const auto udp = std::dynamic_pointer_cast<eprosima::fastdds::rtps::UDPv4TransportDescriptor>(
        qos.transport().user_transports.front());
    ASSERT_NE(udp, nullptr);
    EXPECT_EQ(udp->maxInitialPeersRange, 1u);
}

// A recorder started before the gateway on one host takes participant 0's port: a tool that announced to that
// port alone heard of the gateway only at its next periodic announcement, 20 s later (CI, 2026-11-26).
TEST(PeerTransportTest, APeerOnThisHostIsAnnouncedToAtSeveralParticipants) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    PeerTransport transport;
    transport.peers = {"127.0.0.1", "10.77.0.1"};
    apply_peer_transport(qos, transport, 7);
    std::vector<Peer> expected;
    for (int id = 0; id < SAME_HOST_PEER_PARTICIPANTS; ++id)
        expected.push_back({"127.0.0.1", metatraffic_unicast_port(7, id)});
    expected.push_back({"10.77.0.1", 0});
    EXPECT_EQ(initial_peers(qos), expected);
}

TEST(PeerTransportTest, RefusesAPeerThatIsNeitherAnAddressNorAHostNameNamingTheFlag) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    PeerTransport transport;
    transport.peers = {"base camp"};
    try {
        apply_peer_transport(qos, transport, 7);
        FAIL() << "'base camp' was taken";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()), "--peer: 'base camp' is neither an IPv4 address nor a host name");
    }
}

// A robot on DHCP is known by its name (/etc/hosts here: no resolver is asked over a network in a unit test).
TEST(PeerTransportTest, APeerGivenByHostNameIsAnnouncedToAtItsAddress) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    PeerTransport transport;
    transport.peers = {"localhost"};
    EXPECT_EQ(resolve_peers(transport), (std::vector<std::string>{"127.0.0.1"}));
    apply_peer_transport(qos, transport, 7);
    ASSERT_FALSE(initial_peers(qos).empty());
    EXPECT_EQ(initial_peers(qos).front(), (Peer{"127.0.0.1", metatraffic_unicast_port(7, 0)}));
}

}  // namespace
}  // namespace tgw::base
