#include "gateway/core/urgency_demand.hpp"

#include <gtest/gtest.h>

namespace tgw::core {
namespace {

using namespace std::chrono_literals;

const WireModel WIRE;

TopicLoad topic(const std::string& name, base::Duration ttl, std::uint64_t received, std::uint64_t forwarded,
                std::uint64_t forwarded_wire_bytes, std::uint64_t queued_samples = 0, std::uint64_t queued_bytes = 0) {
    return TopicLoad{name, ttl, received, forwarded, forwarded_wire_bytes, queued_samples, queued_bytes};
}

TEST(UrgencyDemandTest, AStreamThatKeepsUpNeedsItsArrivalRateOnTheWire) {
    // A: 5 samples a second of 238 bytes on the wire, all forwarded.
    const auto demand =
        urgency_demand({topic("A", 1s, 100, 100, 23'800)}, {topic("A", 1s, 110, 110, 26'180)}, 2s, WIRE);
    ASSERT_EQ(demand.size(), 1u);
    EXPECT_EQ(demand[0].ttl, 1s);
    EXPECT_DOUBLE_EQ(demand[0].bps, 5 * 238 * 8);
}

TEST(UrgencyDemandTest, ABacklogMustLeaveWithinItsTtl) {
    // D: 5 a second arrive, 1,210 bytes each on the wire; 100 wait (1,016 bytes of payload each): they need their
    // wire bytes within 20 s on top of the stream.
    const auto demand =
        urgency_demand({topic("D", 20s, 100, 10, 12'100)}, {topic("D", 20s, 105, 10, 12'100, 100, 101'600)}, 1s, WIRE);
    ASSERT_EQ(demand.size(), 1u);
    const double queued_wire = 100.0 * static_cast<double>(WIRE.wire_bytes(1016));
    EXPECT_DOUBLE_EQ(demand[0].bps, 8 * (5 * 1210 + queued_wire / 20));
}

TEST(UrgencyDemandTest, TopicsOfOneTtlAddUpAndUrgenciesComeShortestFirst) {
    const auto demand = urgency_demand(
        {topic("D", 20s, 0, 0, 0), topic("A1", 1s, 0, 0, 0), topic("A2", 1s, 0, 0, 0)},
        {topic("D", 20s, 10, 10, 12'100), topic("A1", 1s, 10, 10, 2'380), topic("A2", 1s, 20, 20, 4'760)}, 1s, WIRE);
    ASSERT_EQ(demand.size(), 2u);
    EXPECT_EQ(demand[0].ttl, 1s);
    EXPECT_DOUBLE_EQ(demand[0].bps, 8 * (2'380 + 4'760));
    EXPECT_EQ(demand[1].ttl, 20s);
    EXPECT_DOUBLE_EQ(demand[1].bps, 8 * 12'100);
}

// A robot whose samples never leave (its share too small) must still show its need, or it would never get more.
TEST(UrgencyDemandTest, SamplesNeverForwardedAreSizedFromTheQueue) {
    const auto demand = urgency_demand({topic("A", 1s, 0, 0, 0)}, {topic("A", 1s, 5, 0, 0, 5, 5 * 41)}, 1s, WIRE);
    ASSERT_EQ(demand.size(), 1u);
    const double per_sample = static_cast<double>(WIRE.wire_bytes(41));
    EXPECT_DOUBLE_EQ(demand[0].bps, 8 * (5 * per_sample + 5 * per_sample / 1));
}

TEST(UrgencyDemandTest, ATopicNewSinceTheLastStatusCountsFromZero) {
    const auto demand = urgency_demand({}, {topic("A", 1s, 5, 5, 1'190)}, 1s, WIRE);
    ASSERT_EQ(demand.size(), 1u);
    EXPECT_DOUBLE_EQ(demand[0].bps, 8 * 1'190);
}

TEST(UrgencyDemandTest, AGatewayThatRestartedCountsOnlyItsQueue) {
    // Counts went down: a new gateway under the same name; its arrivals since are unknown.
    const auto demand =
        urgency_demand({topic("A", 1s, 1000, 1000, 238'000)}, {topic("A", 1s, 3, 3, 714, 2, 82)}, 1s, WIRE);
    ASSERT_EQ(demand.size(), 1u);
    EXPECT_DOUBLE_EQ(demand[0].bps, 8 * (2 * static_cast<double>(WIRE.wire_bytes(41)) / 1));
}

TEST(UrgencyDemandTest, NoTimeNoRate) {
    EXPECT_TRUE(urgency_demand({topic("A", 1s, 0, 0, 0)}, {topic("A", 1s, 5, 5, 1'190)}, 0s, WIRE).empty());
}

TEST(GrantableDemandTest, TheGatewaysOwnTrafficGoesWithTheMostUrgentAndAllIsScaledToItsBudget) {
    const auto granted = grantable_demand({{1s, 19'000}, {20s, 40'000}}, 1'000, 0.95);
    ASSERT_EQ(granted.size(), 2u);
    EXPECT_EQ(granted[0].ttl, 1s);
    EXPECT_DOUBLE_EQ(granted[0].bps, 20'000 / 0.95) << "with the heartbeats and discovery";
    EXPECT_DOUBLE_EQ(granted[1].bps, 40'000 / 0.95);
}

TEST(GrantableDemandTest, NoDemandNoGrantAndAnOddFractionCountsAsWhole) {
    EXPECT_TRUE(grantable_demand({}, 1'000, 0.95).empty());
    EXPECT_DOUBLE_EQ(grantable_demand({{1s, 1'000}}, 0, 0)[0].bps, 1'000);
    EXPECT_DOUBLE_EQ(grantable_demand({{1s, 1'000}}, -5, 1.5)[0].bps, 1'000);
}

TEST(LeastShareTest, RoomForTheStatusWithinItsTtlAndBesideTheMostUrgentSampleWithinThatTtl) {
    // A status of 400 bytes on the wire within 1 s: 3,200 bit/s; with a hazard of 238 bytes within the hazard's
    // TTL of 1 s: 5,104 (the status on the wire must leave the hazard time for its own); the 20-second topic's
    // 1,210-byte samples do not count.
    const std::vector<TopicLoad> topics = {topic("D", 20s, 10, 10, 12'100), topic("A", 1s, 10, 10, 2'380)};
    EXPECT_DOUBLE_EQ(least_share_bps(topics, 400, 1s, WIRE), 3'200 + 1'904);
    EXPECT_DOUBLE_EQ(least_share_bps({}, 100, 1s, WIRE), 800) << "no topic yet";
    const std::vector<TopicLoad> slow = {topic("D", 20s, 10, 10, 12'100)};
    EXPECT_DOUBLE_EQ(least_share_bps(slow, 400, 1s, WIRE), 3'200) << "a long TTL: the status within its own decides";
}

TEST(LeastShareTest, PaysForTheBudgetFractionAndTheTrafficOutsideTheSchedule) {
    // A gateway that budgets 95 % of its rate needs its floor over 0.95 for the status to leave within its TTL.
    EXPECT_DOUBLE_EQ(least_share_bps({}, 400, 1s, WIRE, 0.95), 3'200 / 0.95);
    EXPECT_DOUBLE_EQ(least_share_bps({}, 400, 1s, WIRE, 0.5, 800), (3'200 + 800) / 0.5);
    EXPECT_DOUBLE_EQ(least_share_bps({}, 400, 1s, WIRE, 0), 3'200) << "an odd fraction counts as whole";
    EXPECT_DOUBLE_EQ(least_share_bps({}, 400, 1s, WIRE, 1.5), 3'200);
}

TEST(LeastShareTest, AnUrgentTopicNeverForwardedIsSizedFromWhatWaits) {
    const std::vector<TopicLoad> topics = {topic("A", 500ms, 3, 0, 0, 3, 3 * 1000)};
    EXPECT_DOUBLE_EQ(least_share_bps(topics, 0, 1s, WIRE), 8.0 * static_cast<double>(WIRE.wire_bytes(1000)) / 0.5);
}

}  // namespace
}  // namespace tgw::core
