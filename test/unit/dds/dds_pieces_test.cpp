// The DDS side's pure pieces: topic filter, TTL rule, WAN addresses, passthrough type.
#include <gtest/gtest.h>

#include "base/config_error.hpp"
#include "gateway/dds/passthrough_type.hpp"
#include "gateway/dds/topic_filter.hpp"
#include "gateway/dds/ttl_resolver.hpp"
#include "gateway/dds/wan_address.hpp"

namespace tgw::dds {
namespace {

using namespace std::chrono_literals;

TEST(TopicFilterTest, AdmitsEverythingWithoutGlobs) {
    const TopicFilter sut;
    EXPECT_TRUE(sut.admits("telemetry/A"));
    EXPECT_TRUE(sut.admits("rt/chatter"));
}

TEST(TopicFilterTest, AdmitsOnlyAllowedTopicsWhenAllowGlobsAreGiven) {
    const TopicFilter sut({"telemetry/*", "rt/chatter"}, {});
    EXPECT_TRUE(sut.admits("telemetry/A"));
    EXPECT_TRUE(sut.admits("rt/chatter"));
    EXPECT_FALSE(sut.admits("rt/camera/image"));
}

TEST(TopicFilterTest, DenyWinsOverAllow) {
    const TopicFilter sut({"telemetry/*"}, {"telemetry/D", "*/debug*"});
    EXPECT_TRUE(sut.admits("telemetry/A"));
    EXPECT_FALSE(sut.admits("telemetry/D"));
    EXPECT_FALSE(sut.admits("telemetry/debug/x"));
}

TEST(TtlResolverTest, ProfileWinsOverPublisherAndDefault) {
    const auto sut = resolve_ttl(7s, 3s, 5s);
    EXPECT_EQ(sut.ttl, base::Duration(7s));
    EXPECT_EQ(sut.source, TtlSource::profile);
}

TEST(TtlResolverTest, PublisherLifespanWinsOverDefault) {
    const auto sut = resolve_ttl(std::nullopt, 3s, 5s);
    EXPECT_EQ(sut.ttl, base::Duration(3s));
    EXPECT_EQ(sut.source, TtlSource::publisher);
}

TEST(TtlResolverTest, InfiniteOrZeroLifespansDoNotApply) {
    const auto sut = resolve_ttl(base::Duration::max(), base::Duration::zero(), 5s);
    EXPECT_EQ(sut.ttl, base::Duration(5s));
    EXPECT_EQ(sut.source, TtlSource::fallback);
}

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
        } catch (const base::ConfigError& e) {
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
    EXPECT_THROW(resolve_interface_address("no-such-if0"), base::ConfigError);
}

TEST(WanAddressTest, ResolvesAnInterfaceNameFromItsAddress) {
    EXPECT_EQ(resolve_interface_name("lo"), "lo");
    EXPECT_EQ(resolve_interface_name("127.0.0.1"), "lo");
    EXPECT_THROW(resolve_interface_name("192.0.2.77"), base::ConfigError);  // TEST-NET-1: on no interface here
}

TEST(PassthroughTypeTest, SerializesThePayloadUntouched) {
    PassthroughType sut("any::Type", false);
    PassthroughData in;
    in.payload = {0x00, 0x01, 0x00, 0x00, 1, 2, 3, 4, 5};
    eprosima::fastrtps::rtps::SerializedPayload_t payload(4);
    ASSERT_TRUE(sut.serialize(&in, &payload));
    EXPECT_EQ(payload.length, in.payload.size());
    EXPECT_EQ(payload.encapsulation, CDR_LE);
    PassthroughData out;
    ASSERT_TRUE(sut.deserialize(&payload, &out));
    EXPECT_EQ(out.payload, in.payload);
    EXPECT_STREQ(sut.getName(), "any::Type");
}

TEST(PassthroughTypeTest, KeyIsTheCarriedKeyHashOrTheUnknownInstance) {
    PassthroughType sut("any::Keyed", true);
    PassthroughData data;
    eprosima::fastrtps::rtps::InstanceHandle_t handle;
    ASSERT_TRUE(sut.getKey(&data, &handle));
    EXPECT_EQ(handle, PassthroughType::UNKNOWN_INSTANCE);
    data.key.value[0] = 42;
    ASSERT_TRUE(sut.getKey(&data, &handle));
    EXPECT_EQ(handle, data.key);
    PassthroughType unkeyed("any::Unkeyed", false);
    EXPECT_FALSE(unkeyed.getKey(&data, &handle));
}

}  // namespace
}  // namespace tgw::dds
