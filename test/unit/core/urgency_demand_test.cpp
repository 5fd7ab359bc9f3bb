#include "core/urgency_demand.hpp"

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

// A robot that starts publishing: its first status, 0.4 s in, has A's first 3 samples. Counted over the 2 s since
// the status before, that is 1.5 a second, where 5 come.
TEST(UrgencyDemandTest, ATopicThatBeganWithinTheWindowCountsOverTheTimeSinceItsFirstSample) {
    TopicLoad began = topic("A", 1s, 3, 3, 3 * 238);
    began.active_for = 400ms;
    auto demand = urgency_demand({topic("A", 1s, 0, 0, 0)}, {began}, 2s, WIRE);
    ASSERT_EQ(demand.size(), 1u);
    EXPECT_DOUBLE_EQ(demand[0].bps, 8 * 3 * 238 / base::to_seconds(MIN_ACTIVE)) << "half a second at least";

    began = topic("A", 1s, 8, 8, 8 * 238);
    began.active_for = 1600ms;
    demand = urgency_demand({topic("A", 1s, 0, 0, 0)}, {began}, 2s, WIRE);
    EXPECT_DOUBLE_EQ(demand[0].bps, 8 * 8 * 238 / 1.6);

    // A topic that had samples before counts over the whole window, however long it has been active.
    TopicLoad going = topic("A", 1s, 110, 110, 110 * 238);
    going.active_for = 30s;
    demand = urgency_demand({topic("A", 1s, 100, 100, 100 * 238)}, {going}, 2s, WIRE);
    EXPECT_DOUBLE_EQ(demand[0].bps, 8 * 5 * 238);
    going.active_for = 1s;  // not more than the window, either
    demand = urgency_demand({topic("A", 1s, 0, 0, 0)}, {going}, 500ms, WIRE);
    EXPECT_DOUBLE_EQ(demand[0].bps, 8 * 110 * 238 / 0.5);
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

/// `topic`'s load after forwarding `forwarded` samples of `payload_bytes` each (their wire bytes as alone).
TopicLoad forwarded(const std::string& name, base::Duration ttl, std::uint64_t forwarded, std::size_t payload_bytes) {
    TopicLoad t = topic(name, ttl, forwarded, forwarded, forwarded * WIRE.wire_bytes(payload_bytes));
    t.forwarded_payload_bytes = forwarded * payload_bytes;
    return t;
}

/// Bits of a status of 226 bytes (402 on the wire by itself in standard mode) and of a 64-byte hazard (238).
const double STATUS_BITS = 8.0 * 402;
const double HAZARD_BITS = 8.0 * 238;

TEST(LeastShareTest, RoomForTheStatusWithinItsTtlAndBesideTheMostUrgentSampleWithinThatTtl) {
    ASSERT_EQ(WIRE.wire_bytes(226), 402u);
    ASSERT_EQ(WIRE.wire_bytes(64), 238u);
    // The status within 1 s: 3,216 bit/s; with the hazard within the hazard's TTL of 1 s: 5,120 (the status on the
    // wire must leave the hazard time for its own); the 20-second topic's 1,016-byte samples do not count.
    const std::vector<TopicLoad> topics = {forwarded("D", 20s, 10, 1'016), forwarded("A", 1s, 10, 64)};
    EXPECT_DOUBLE_EQ(least_share_bps(topics, 226, 1s, {WIRE}), STATUS_BITS + HAZARD_BITS);
    EXPECT_DOUBLE_EQ(least_share_bps({}, 226, 1s, {WIRE}), STATUS_BITS) << "no topic yet";
    const std::vector<TopicLoad> slow = {forwarded("D", 20s, 10, 1'016)};
    EXPECT_DOUBLE_EQ(least_share_bps(slow, 226, 1s, {WIRE}), STATUS_BITS)
        << "a long TTL: the status within its own decides";
}

// In compact mode the status too long to share a bundle with the hazard goes in one of its own, and the hazard in
// another: each pays a bundle's frame and a datagram's headers.
TEST(LeastShareTest, InCompactModeTheStatusAndTheHazardEachPayForABundleOfTheirOwn) {
    const AloneWire compact{WIRE, true};
    const std::vector<TopicLoad> topics = {forwarded("A", 1s, 10, 64)};
    const double expected = 8.0 * static_cast<double>(compact.wire_bytes(720, true) + compact.wire_bytes(64));
    EXPECT_DOUBLE_EQ(least_share_bps(topics, 720, 1s, compact), expected);
    // 9,952 bit/s, against 7,824 for the same two as DDS samples of their own.
    EXPECT_GT(expected, least_share_bps(topics, 720, 1s, {WIRE}));
    EXPECT_GT(compact.wire_bytes(64), WIRE.wire_bytes(64)) << "a bundle's frame on top of the DDS sample's headers";
}

TEST(LeastShareTest, PaysForTheBudgetFractionAndTheTrafficOutsideTheSchedule) {
    // A gateway that budgets 95 % of its rate needs its floor over 0.95 for the status to leave within its TTL.
    EXPECT_DOUBLE_EQ(least_share_bps({}, 226, 1s, {WIRE}, 0.95), STATUS_BITS / 0.95);
    EXPECT_DOUBLE_EQ(least_share_bps({}, 226, 1s, {WIRE}, 0.5, 800), (STATUS_BITS + 800) / 0.5);
    EXPECT_DOUBLE_EQ(least_share_bps({}, 226, 1s, {WIRE}, 0), STATUS_BITS) << "an odd fraction counts as whole";
    EXPECT_DOUBLE_EQ(least_share_bps({}, 226, 1s, {WIRE}, 1.5), STATUS_BITS);
}

TEST(LeastShareTest, AnUrgentTopicNeverForwardedIsSizedFromWhatWaits) {
    const std::vector<TopicLoad> topics = {topic("A", 500ms, 3, 0, 0, 3, 3 * 1000)};
    const double status_bits = 8.0 * static_cast<double>(WIRE.wire_bytes(0));
    EXPECT_DOUBLE_EQ(least_share_bps(topics, 0, 1s, {WIRE}),
                     (status_bits + 8.0 * static_cast<double>(WIRE.wire_bytes(1000))) / 0.5);
}

}  // namespace
}  // namespace tgw::core
