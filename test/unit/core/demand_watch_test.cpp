#include "gateway/core/demand_watch.hpp"

#include <gtest/gtest.h>

namespace tgw::core {
namespace {

using namespace std::chrono_literals;

const WireModel WIRE;
const base::SteadyTime T0{1000s};

/// A hazard topic (TTL 1 s) `received` samples in, all forwarded at 238 bytes each on the wire.
std::vector<TopicLoad> hazards(std::uint64_t received) {
    return {TopicLoad{"hazard", 1s, received, received, received * 238, 0, 0}};
}

/// A status made at `at` with `loads` that left for the base camp.
void tell(DemandWatch& watch, base::SteadyTime at, const std::vector<TopicLoad>& loads) {
    watch.sent(at, loads);
    watch.delivered(true);
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
    EXPECT_TRUE(watch.changed(T0, hazards(0))) << "the base camp has heard nothing yet";
    watch.sent(T0, hazards(0));
    EXPECT_FALSE(watch.changed(T0 + 1s, hazards(0))) << "its fate unknown";
    watch.delivered(false);  // expired in the gateway's queue
    EXPECT_TRUE(watch.changed(T0 + 2s, hazards(0))) << "again";
    tell(watch, T0 + 2s, hazards(0));
    EXPECT_FALSE(watch.changed(T0 + 3s, hazards(0))) << "told, and nothing new";
}

TEST(DemandWatchTest, HazardsThatStartAfterAStatusAskForTheNextOneWithinTheWindow) {
    DemandWatch watch({}, WIRE);
    // Quiet: one sample a second, told in the second status (the first tells only what waits: nothing).
    watch.changed(T0, hazards(0));
    tell(watch, T0, hazards(0));
    EXPECT_DOUBLE_EQ(watch.told()[0].bps, 0) << "the first status: nothing waits";
    watch.changed(T0 + 1s, hazards(1));
    tell(watch, T0 + 1s, hazards(1));
    EXPECT_DOUBLE_EQ(watch.told()[0].bps, 238 * 8) << "one sample over the first second";
    watch.changed(T0 + 2s, hazards(2));
    EXPECT_FALSE(watch.changed(T0 + 3s, hazards(3))) << "nothing new";
    // Then 10 samples a second: 19,040 bit/s.
    EXPECT_TRUE(watch.changed(T0 + 4s, hazards(13))) << "over the last 2 s: 5 a second";
}

TEST(DemandWatchTest, AStatusThatToldTheNewDemandOnlyInPartAsksForAnother) {
    DemandWatch watch({}, WIRE);
    // One sample a second; statuses at 1 s and, by their spacing, at 10 s. Hazards at 10 a second from 9.5 s on:
    // the status at 10 s tells them averaged over its 9 s.
    for (int s = 0; s <= 9; ++s) {
        watch.changed(T0 + s * 1s, hazards(static_cast<std::uint64_t>(s)));
        if (s == 1)
            tell(watch, T0 + 1s, hazards(1));
    }
    watch.changed(T0 + 10s, hazards(15));
    tell(watch, T0 + 10s, hazards(15));
    EXPECT_NEAR(watch.told()[0].bps, 14.0 / 9 * 238 * 8, 1e-6);
    ASSERT_TRUE(watch.changed(T0 + 11s, hazards(25))) << "8 a second over the last 2 s";
    tell(watch, T0 + 11s, hazards(25));
    EXPECT_NEAR(watch.told()[0].bps, 10 * 238 * 8, 1e-6) << "from the status at 10 s: 10 samples in 1 s";
    EXPECT_FALSE(watch.changed(T0 + 12s, hazards(35))) << "told";
}

TEST(DemandWatchTest, ADemandThatDwindlesIsToldToo) {
    DemandWatch watch({}, WIRE);
    watch.changed(T0, hazards(0));
    tell(watch, T0, hazards(0));
    watch.changed(T0 + 1s, hazards(10));
    tell(watch, T0 + 1s, hazards(10));  // 10 a second over the first period
    watch.changed(T0 + 2s, hazards(20));
    EXPECT_FALSE(watch.changed(T0 + 3s, hazards(30)));
    watch.changed(T0 + 4s, hazards(30));
    EXPECT_TRUE(watch.changed(T0 + 5s, hazards(30))) << "nothing for 2 s: the grant should go to others";
}

TEST(DemandWatchTest, AStatusDroppedBeforeItLeftToldNothing) {
    DemandWatch watch({}, WIRE);
    watch.changed(T0, hazards(0));
    tell(watch, T0, hazards(0));
    watch.changed(T0 + 1s, hazards(1));
    tell(watch, T0 + 1s, hazards(1));
    watch.changed(T0 + 2s, hazards(2));
    ASSERT_TRUE(watch.changed(T0 + 3s, hazards(13)));
    watch.sent(T0 + 3s, hazards(13));
    EXPECT_FALSE(watch.changed(T0 + 4s, hazards(23))) << "its fate unknown: no second status yet";
    watch.delivered(false);  // expired in the gateway's queue
    EXPECT_DOUBLE_EQ(watch.told()[0].bps, 238 * 8) << "still what the first status told";
    EXPECT_TRUE(watch.changed(T0 + 5s, hazards(33))) << "asks again";
}

}  // namespace
}  // namespace tgw::core
