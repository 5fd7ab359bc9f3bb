#include "core/demand_watch.hpp"

#include <gtest/gtest.h>

namespace tgw::core {
namespace {

using namespace std::chrono_literals;

const WireModel WIRE;
const base::SteadyTime T0{1000s};
/// A compact robot's status on the wire (about 700 bytes).
constexpr double STATUS_BITS = 5600;
/// A rate at which the statuses' share never holds one back.
constexpr double FAST = 1e9;

/// A hazard topic (TTL 1 s) `received` samples in, all forwarded at 238 bytes each on the wire.
std::vector<TopicLoad> hazards(std::uint64_t received) {
    return {TopicLoad{"hazard", 1s, received, received, received * 238, 0, 0}};
}

/// A status made at `at` with `loads` that left for the base camp.
void tell(DemandWatch& watch, base::SteadyTime at, const std::vector<TopicLoad>& loads) {
    watch.sent(at, loads, STATUS_BITS);
    watch.delivered(true, at);
}

/// Statuses at T0 - 1 s and T0 that left for the base camp: it was told one sample a second of `loads` (called with
/// the count received).
template <typename Loads>
void told_one_a_second(DemandWatch& watch, Loads loads, double rate) {
    watch.changed(T0 - 1s, loads(0), rate);
    tell(watch, T0 - 1s, loads(0));
    watch.changed(T0, loads(1), rate);
    tell(watch, T0, loads(1));
}

TEST(DemandChangedTest, OnlyAMoveBeyondBothTheFractionAndTheFloorCounts) {
    const std::vector<UrgencyDemand> told{{1s, 10'000}, {20s, 40'000}};
    EXPECT_FALSE(demand_changed(told, {{1s, 12'000}, {20s, 40'000}}, 0.25, 1000)) << "20 %";
    EXPECT_TRUE(demand_changed(told, {{1s, 13'000}, {20s, 40'000}}, 0.25, 1000)) << "30 %";
    EXPECT_TRUE(demand_changed(told, {{1s, 7'000}, {20s, 40'000}}, 0.25, 1000)) << "down 30 %";
    EXPECT_FALSE(demand_changed({{1s, 100}}, {{1s, 900}}, 0.25, 1000)) << "within the floor";
    EXPECT_TRUE(demand_changed(told, {{1s, 10'000}, {5s, 2'000}, {20s, 40'000}}, 0.25, 1000)) << "a new urgency";
    EXPECT_TRUE(demand_changed(told, {{20s, 40'000}}, 0.25, 1000)) << "an urgency gone";
}

TEST(DemandWatchTest, AsksForAStatusUntilOneHasLeft) {
    DemandWatch watch({}, WIRE);
    EXPECT_TRUE(watch.changed(T0, hazards(0), FAST)) << "the base camp has heard nothing yet";
    watch.sent(T0, hazards(0), STATUS_BITS);
    EXPECT_FALSE(watch.changed(T0 + 1s, hazards(0), FAST)) << "its fate unknown";
    watch.delivered(false, T0 + 2s);  // expired in the gateway's queue
    EXPECT_TRUE(watch.changed(T0 + 2s, hazards(0), FAST)) << "again";
    tell(watch, T0 + 2s, hazards(0));
    EXPECT_FALSE(watch.changed(T0 + 3s, hazards(0), FAST)) << "told, and nothing new";
}

TEST(DemandWatchTest, HazardsThatStartAfterAStatusAskForTheNextOneWithinTheWindow) {
    DemandWatch watch({}, WIRE);
    // Quiet: one sample a second, told in the second status (the first tells only what waits: nothing).
    watch.changed(T0, hazards(0), FAST);
    tell(watch, T0, hazards(0));
    EXPECT_DOUBLE_EQ(watch.told()[0].bps, 0) << "the first status: nothing waits";
    watch.changed(T0 + 1s, hazards(1), FAST);
    tell(watch, T0 + 1s, hazards(1));
    EXPECT_DOUBLE_EQ(watch.told()[0].bps, 238 * 8) << "one sample over the first second";
    watch.changed(T0 + 2s, hazards(2), FAST);
    EXPECT_FALSE(watch.changed(T0 + 3s, hazards(3), FAST)) << "nothing new";
    // Then 10 samples a second: 19,040 bit/s.
    EXPECT_TRUE(watch.changed(T0 + 4s, hazards(13), FAST)) << "over the last 2 s: 5 a second";
}

TEST(DemandWatchTest, AStatusThatToldTheNewDemandOnlyInPartAsksForAnother) {
    DemandWatch watch({}, WIRE);
    // One sample a second; statuses at 1 s and, by their spacing, at 10 s. Hazards at 10 a second from 9.5 s on:
    // the status at 10 s tells them averaged over its 9 s.
    for (int s = 0; s <= 9; ++s) {
        watch.changed(T0 + s * 1s, hazards(static_cast<std::uint64_t>(s)), FAST);
        if (s == 1)
            tell(watch, T0 + 1s, hazards(1));
    }
    watch.changed(T0 + 10s, hazards(15), FAST);
    tell(watch, T0 + 10s, hazards(15));
    EXPECT_NEAR(watch.told()[0].bps, 14.0 / 9 * 238 * 8, 1e-6);
    ASSERT_TRUE(watch.changed(T0 + 11s, hazards(25), FAST)) << "8 a second over the last 2 s";
    tell(watch, T0 + 11s, hazards(25));
    EXPECT_NEAR(watch.told()[0].bps, 10 * 238 * 8, 1e-6) << "from the status at 10 s: 10 samples in 1 s";
    EXPECT_FALSE(watch.changed(T0 + 12s, hazards(35), FAST)) << "told";
}

TEST(DemandWatchTest, ADemandThatDwindlesIsToldToo) {
    DemandWatch watch({}, WIRE);
    watch.changed(T0, hazards(0), FAST);
    tell(watch, T0, hazards(0));
    watch.changed(T0 + 1s, hazards(10), FAST);
    tell(watch, T0 + 1s, hazards(10));  // 10 a second over the first period
    watch.changed(T0 + 2s, hazards(20), FAST);
    EXPECT_FALSE(watch.changed(T0 + 3s, hazards(30), FAST));
    watch.changed(T0 + 4s, hazards(30), FAST);
    EXPECT_TRUE(watch.changed(T0 + 5s, hazards(30), FAST)) << "nothing for 2 s: the grant should go to others";
}

TEST(DemandWatchTest, AStatusDroppedBeforeItLeftToldNothing) {
    DemandWatch watch({}, WIRE);
    watch.changed(T0, hazards(0), FAST);
    tell(watch, T0, hazards(0));
    watch.changed(T0 + 1s, hazards(1), FAST);
    tell(watch, T0 + 1s, hazards(1));
    watch.changed(T0 + 2s, hazards(2), FAST);
    ASSERT_TRUE(watch.changed(T0 + 3s, hazards(13), FAST));
    watch.sent(T0 + 3s, hazards(13), STATUS_BITS);
    EXPECT_FALSE(watch.changed(T0 + 4s, hazards(23), FAST)) << "its fate unknown: no second status yet";
    watch.delivered(false, T0 + 5s);  // expired in the gateway's queue
    EXPECT_DOUBLE_EQ(watch.told()[0].bps, 238 * 8) << "still what the first status told";
    EXPECT_TRUE(watch.changed(T0 + 5s, hazards(33), FAST)) << "asks again";
}

TEST(DemandWatchTest, StatusesForTheDemandTakeAtMostTheirShareOfTheRate) {
    // At 12,000 bit/s a 5,600-bit status every second would take 47 % of the rate: 0.2 of it allows one every
    // 2.33 s, counted from when the last one left.
    constexpr double RATE = 12'000;
    DemandWatch watch({}, WIRE);
    // Hazards told at one a second: what follows is more of them, not a more urgent kind.
    told_one_a_second(watch, hazards, RATE);
    ASSERT_DOUBLE_EQ(watch.told()[0].bps, 238 * 8);
    EXPECT_FALSE(watch.changed(T0 + 1s, hazards(10), RATE)) << "the demand moved, but a status left 1 s ago";
    EXPECT_FALSE(watch.changed(T0 + 2s, hazards(20), RATE)) << "2 s ago";
    ASSERT_TRUE(watch.changed(T0 + 2400ms, hazards(22), RATE)) << "2.4 s ago";
    watch.sent(T0 + 2400ms, hazards(22), STATUS_BITS);
    watch.delivered(true, T0 + 5s);  // it waited in the queue, and left just before
    EXPECT_FALSE(watch.changed(T0 + 6s, hazards(100), RATE)) << "1 s after it left";
    ASSERT_TRUE(watch.changed(T0 + 7400ms, hazards(150), RATE)) << "2.4 s after it left";
    watch.sent(T0 + 7400ms, hazards(150), STATUS_BITS);
    watch.delivered(false, T0 + 8s);
    EXPECT_TRUE(watch.changed(T0 + 9s, hazards(200), RATE)) << "a status dropped on the robot cost the link nothing";
}

TEST(MoreUrgentThanToldTest, OnlyAnUrgencyAboveTheFloorAheadOfEveryToldOneCounts) {
    EXPECT_TRUE(more_urgent_than_told({}, {{1s, 2'000}}, 1000)) << "told nothing";
    EXPECT_TRUE(more_urgent_than_told({{1s, 0}}, {{1s, 2'000}}, 1000)) << "told it idle";
    EXPECT_TRUE(more_urgent_than_told({{20s, 40'000}}, {{1s, 2'000}, {20s, 40'000}}, 1000)) << "hazards begin";
    EXPECT_FALSE(more_urgent_than_told({{1s, 2'000}}, {{1s, 20'000}}, 1000)) << "more of the same urgency";
    EXPECT_FALSE(more_urgent_than_told({{1s, 2'000}}, {{1s, 2'000}, {20s, 40'000}}, 1000)) << "pictures begin";
    EXPECT_FALSE(more_urgent_than_told({{20s, 40'000}}, {{1s, 900}, {20s, 40'000}}, 1000)) << "within the floor";
    EXPECT_FALSE(more_urgent_than_told({{1s, 2'000}}, {}, 1000)) << "nothing now";
}

/// A picture topic (TTL 20 s) `received` samples in, all forwarded at 7,000 bytes each on the wire.
std::vector<TopicLoad> pictures(std::uint64_t received) {
    return {TopicLoad{"picture", 20s, received, received, received * 7000, 0, 0}};
}

std::vector<TopicLoad> pictures_and_hazards(std::uint64_t pictures_in, std::uint64_t hazards_in) {
    std::vector<TopicLoad> loads = pictures(pictures_in);
    loads.push_back(hazards(hazards_in).front());
    return loads;
}

TEST(DemandWatchTest, HazardsThatBeginOnAShareToldForLessGoAtOnceOnce) {
    // 12,000 bit/s allows a status every 2.33 s (StatusesForTheDemandTakeAtMostTheirShareOfTheRate); the one that
    // tells of hazards, more urgent than anything the base camp knows of, does not wait for that.
    constexpr double RATE = 12'000;
    DemandWatch watch({}, WIRE);
    told_one_a_second(watch, pictures, RATE);
    ASSERT_TRUE(watch.changed(T0 + 1s, pictures_and_hazards(2, 5), RATE)) << "hazards, 1 s after a status left";
    watch.sent(T0 + 1s, pictures_and_hazards(2, 5), STATUS_BITS);
    EXPECT_FALSE(watch.changed(T0 + 1200ms, pictures_and_hazards(2, 6), RATE)) << "its fate unknown";
    watch.delivered(true, T0 + 1500ms);
    EXPECT_FALSE(watch.changed(T0 + 2s, pictures_and_hazards(3, 20), RATE)) << "told: more hazards wait their turn";
    EXPECT_TRUE(watch.changed(T0 + 4s, pictures_and_hazards(5, 40), RATE)) << "2.5 s after it left";
}

TEST(DemandWatchTest, HazardsOfARobotThatToldNothingGoAtOnce) {
    constexpr double RATE = 3'000;  // a quiet robot's floor
    DemandWatch watch({}, WIRE);
    watch.changed(T0, hazards(0), RATE);
    tell(watch, T0, hazards(0));
    ASSERT_TRUE(watch.changed(T0 + 1s, hazards(5), RATE)) << "the spacing would be 9 s";
}

TEST(DemandWatchTest, PicturesThatBeginAfterHazardsWaitForTheSpacing) {
    constexpr double RATE = 12'000;
    DemandWatch watch({}, WIRE);
    told_one_a_second(watch, hazards, RATE);
    EXPECT_FALSE(watch.changed(T0 + 1s, pictures_and_hazards(1, 2), RATE)) << "less urgent than the hazards";
    EXPECT_TRUE(watch.changed(T0 + 2400ms, pictures_and_hazards(3, 3), RATE));
}

}  // namespace
}  // namespace tgw::core
