#include "base/host_transport.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include "base/interface_addresses.hpp"
#include "base/loopback_transport.hpp"

namespace tgw::base {
namespace {

namespace rtps = eprosima::fastrtps::rtps;
using eprosima::fastdds::rtps::SharedMemTransportDescriptor;
using eprosima::fastdds::rtps::UDPv4TransportDescriptor;

std::vector<std::string> initial_peers(const eprosima::fastdds::dds::DomainParticipantQos& qos) {
    std::vector<std::string> peers;
    for (const auto& locator : qos.wire_protocol().builtin.initialPeersList)
        peers.push_back(rtps::IPLocator::ip_to_string(locator) + ":" + std::to_string(locator.port));
    return peers;
}

template <typename Descriptor>
std::shared_ptr<Descriptor> find_transport(const eprosima::fastdds::dds::DomainParticipantQos& qos) {
    for (const auto& each : qos.transport().user_transports) {
        if (auto found = std::dynamic_pointer_cast<Descriptor>(each))
            return found;
    }
    return nullptr;
}

/// The UDP descriptor the participant gets, whether alone or under a LoopbackTransportDescriptor.
const UDPv4TransportDescriptor* udp_of(const eprosima::fastdds::dds::DomainParticipantQos& qos) {
    if (auto loopback = find_transport<LoopbackTransportDescriptor>(qos))
        return dynamic_cast<const UDPv4TransportDescriptor*>(loopback->low_level_descriptor.get());
    return find_transport<UDPv4TransportDescriptor>(qos).get();
}

rtps::Locator_t udp_locator(const std::string& address, std::uint32_t port) {
    rtps::Locator_t locator;
    locator.kind = LOCATOR_KIND_UDPv4;
    rtps::IPLocator::setIPv4(locator, address);
    locator.port = port;
    return locator;
}

TEST(HostTransportTest, OnLoopbackItAnnouncesItselfToEveryParticipantIndexThere) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    apply_host_transport(qos, 3, {{"127.0.0.1"}});
    EXPECT_FALSE(qos.transport().use_builtin_transports);
    ASSERT_NE(find_transport<LoopbackTransportDescriptor>(qos), nullptr);
    ASSERT_NE(udp_of(qos), nullptr);
    EXPECT_EQ(udp_of(qos)->interfaceWhiteList, (std::vector<std::string>{"127.0.0.1"}));
    // Port 0: Fast DDS fills in each index's discovery port, up to the range.
    EXPECT_EQ(initial_peers(qos), (std::vector<std::string>{"127.0.0.1:0"}));
    EXPECT_EQ(udp_of(qos)->maxInitialPeersRange, PARTICIPANT_INDEXES);
}

TEST(HostTransportTest, OffersNoSharedMemoryUnlessAsked) {
    eprosima::fastdds::dds::DomainParticipantQos plain;
    apply_host_transport(plain, 0, {{"127.0.0.1"}});
    EXPECT_EQ(find_transport<SharedMemTransportDescriptor>(plain), nullptr);
    eprosima::fastdds::dds::DomainParticipantQos with_shm;
    apply_host_transport(with_shm, 0, {{"127.0.0.1"}, true});
    EXPECT_NE(find_transport<SharedMemTransportDescriptor>(with_shm), nullptr);
}

TEST(HostTransportTest, AnAddressOffLoopbackKeepsTheMulticastGroup) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    apply_host_transport(qos, 2, {{"127.0.0.1", "192.168.1.20"}});
    EXPECT_EQ(initial_peers(qos), (std::vector<std::string>{"127.0.0.1:0", "239.255.0.1:7900"}));
    eprosima::fastdds::dds::DomainParticipantQos lan_only;
    apply_host_transport(lan_only, 0, {{"192.168.1.20"}});
    EXPECT_EQ(find_transport<LoopbackTransportDescriptor>(lan_only), nullptr);
    EXPECT_EQ(initial_peers(lan_only), (std::vector<std::string>{"239.255.0.1:7400"}));
}

TEST(HostTransportTest, OnEveryInterfaceUdpIsPlainAndAnnouncesBothWays) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    apply_host_transport(qos, 0, {});
    EXPECT_EQ(find_transport<LoopbackTransportDescriptor>(qos), nullptr);
    ASSERT_NE(udp_of(qos), nullptr);
    EXPECT_TRUE(udp_of(qos)->interfaceWhiteList.empty());
    EXPECT_EQ(initial_peers(qos), (std::vector<std::string>{"127.0.0.1:0", "239.255.0.1:7400"}));
}

TEST(HostTransportTest, InitialPeersFromTheProfileStand) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    qos.wire_protocol().builtin.initialPeersList.push_back(udp_locator("127.0.0.1", 7412));
    apply_host_transport(qos, 0, {{"127.0.0.1"}});
    EXPECT_EQ(initial_peers(qos), (std::vector<std::string>{"127.0.0.1:7412"}));
}

/// The transport under the participant: what it answers a process announcing one of the host's other addresses.
class LoopbackTransportTest : public ::testing::Test {
  protected:
    void SetUp() override {
        auto udp = std::make_shared<UDPv4TransportDescriptor>();
        udp->interfaceWhiteList = {"127.0.0.1"};
        descriptor_ = std::make_shared<LoopbackTransportDescriptor>(udp);
        transport_.reset(static_cast<LoopbackTransport*>(descriptor_->create_transport()));
        ASSERT_TRUE(transport_->init());
    }

    std::shared_ptr<LoopbackTransportDescriptor> descriptor_;
    std::unique_ptr<LoopbackTransport> transport_;
};

TEST_F(LoopbackTransportTest, AnAddressOfThisHostIsAnsweredOnLoopbackAtItsPort) {
    const auto host = interface_addresses();
    ASSERT_TRUE(host.has_value());
    const auto other = std::find_if(host->begin(), host->end(),
                                    [](const InterfaceAddress& each) { return !is_loopback_ipv4(each.address); });
    if (other == host->end())
        GTEST_SKIP() << "this host has no address but loopback";
    rtps::Locator_t result;
    ASSERT_TRUE(transport_->transform_remote_locator(udp_locator(other->address, 7411), result));
    EXPECT_EQ(rtps::IPLocator::ip_to_string(result), "127.0.0.1");
    EXPECT_EQ(result.port, 7411u);
}

TEST_F(LoopbackTransportTest, LoopbackStaysAndAnotherHostIsLeftToUdp) {
    rtps::Locator_t result;
    ASSERT_TRUE(transport_->transform_remote_locator(udp_locator("127.0.0.1", 7413), result));
    EXPECT_EQ(rtps::IPLocator::ip_to_string(result), "127.0.0.1");
    // 192.0.2.77 (TEST-NET-1) is no address of this host: the UDP transport's own answer, not loopback.
    rtps::Locator_t remote_result;
    ASSERT_TRUE(transport_->transform_remote_locator(udp_locator("192.0.2.77", 7410), remote_result));
    EXPECT_EQ(rtps::IPLocator::ip_to_string(remote_result), "192.0.2.77");
}

}  // namespace
}  // namespace tgw::base
