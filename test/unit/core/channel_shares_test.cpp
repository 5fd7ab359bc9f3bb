#include "core/channel_shares.hpp"

#include <gtest/gtest.h>

#include <random>

#include "test/fakes/fake_clock.hpp"

namespace tgw::core {
namespace {

using namespace std::chrono_literals;

constexpr base::Duration A_TTL = 1s;
constexpr base::Duration B_TTL = 2s;
constexpr base::Duration D_TTL = 20s;

double total(const ChannelGrants& grants) {
    double sum = 0;
    for (const auto& [robot, bps] : grants)
        sum += bps;
    return sum;
}

TEST(SplitChannelTest, WhatFitsIsGrantedAndWhatIsLeftIsSharedEqually) {
    const ChannelGrants grants =
        split_channel(60'000, {{"rover1", {{A_TTL, 10'000}, {D_TTL, 10'000}}}, {"rover2", {{A_TTL, 20'000}}}}, 0);
    // 40,000 asked for, 20,000 left: 10,000 more each.
    EXPECT_DOUBLE_EQ(grants.at("rover1"), 30'000);
    EXPECT_DOUBLE_EQ(grants.at("rover2"), 30'000);
}

// The fleet's priority inversion: with equal shares, rover2's 20-second D takes half the channel while rover1's
// hazard messages (A, TTL 1 s) need more than the other half.
TEST(SplitChannelTest, ARobotsUrgentSamplesGoBeforeAnotherRobotsPatientOnes) {
    const ChannelDemands demands = {{"rover1", {{A_TTL, 20'000}}}, {"rover2", {{D_TTL, 40'000}}}};
    const ChannelGrants by_urgency = split_channel(30'000, demands, 0);
    EXPECT_DOUBLE_EQ(by_urgency.at("rover1"), 20'000);
    EXPECT_DOUBLE_EQ(by_urgency.at("rover2"), 10'000);
    const ChannelGrants equal = equal_shares(30'000, demands);
    EXPECT_DOUBLE_EQ(equal.at("rover1"), 15'000);  // A does not fit: what urgency-first shares avoid
    EXPECT_DOUBLE_EQ(equal.at("rover2"), 15'000);
}

TEST(SplitChannelTest, AnUrgencyThatDoesNotFitIsSharedInProportionToDemand) {
    const ChannelGrants grants = split_channel(
        30'000,
        {{"rover1", {{A_TTL, 10'000}, {B_TTL, 20'000}}}, {"rover2", {{A_TTL, 5'000}}}, {"rover3", {{B_TTL, 10'000}}}},
        0);
    // A: 15,000 granted; B: 30,000 asked for, 15,000 left, half of each robot's B.
    EXPECT_DOUBLE_EQ(grants.at("rover1"), 10'000 + 10'000);
    EXPECT_DOUBLE_EQ(grants.at("rover2"), 5'000);
    EXPECT_DOUBLE_EQ(grants.at("rover3"), 5'000);
}

TEST(SplitChannelTest, EveryRobotKeepsItsFloorEvenWithNothingWaiting) {
    // The floor carries a gateway's status and discovery, and lets its first sample go.
    const ChannelGrants grants =
        split_channel(30'000, {{"idle", {}}, {"busy", {{A_TTL, 50'000}}}}, /*floor_bps=*/2'000);
    EXPECT_DOUBLE_EQ(grants.at("idle"), 2'000);
    EXPECT_DOUBLE_EQ(grants.at("busy"), 28'000);
}

TEST(SplitChannelTest, AFloorLargerThanTheChannelAllowsIsCutToAnEqualShare) {
    const ChannelGrants grants = split_channel(3'000, {{"a", {}}, {"b", {}}, {"c", {}}}, 5'000);
    for (const auto& [robot, bps] : grants)
        EXPECT_DOUBLE_EQ(bps, 1'000) << robot;
}

TEST(SplitChannelTest, ARobotsOwnFloorAboveTheCommonOneCountsAgainstItsMostUrgentDemand) {
    // rover1 needs 6,400 bit/s to get its status and one hazard through; rover2 only the common floor.
    const ChannelGrants grants = split_channel(30'000, {{"rover1", {{A_TTL, 5'000}}}, {"rover2", {{D_TTL, 40'000}}}},
                                               2'000, {{"rover1", 6'400}, {"rover2", 500}});
    EXPECT_DOUBLE_EQ(grants.at("rover1"), 6'400) << "its floor covers its 5,000 of A";
    EXPECT_DOUBLE_EQ(grants.at("rover2"), 30'000 - 6'400);
}

TEST(SplitChannelTest, FloorsThatAddUpToMoreThanTheChannelAreCutInProportion) {
    const ChannelGrants grants = split_channel(6'000, {{"a", {}}, {"b", {}}}, 1'000, {{"a", 6'000}});
    EXPECT_DOUBLE_EQ(grants.at("a"), 6'000.0 * 6 / 7);
    EXPECT_DOUBLE_EQ(grants.at("b"), 6'000.0 * 1 / 7);
}

TEST(SplitChannelTest, NoChannelNoGrants) {
    const ChannelGrants grants = split_channel(0, {{"rover1", {{A_TTL, 1'000}}}}, 500);
    EXPECT_DOUBLE_EQ(grants.at("rover1"), 0);
    EXPECT_TRUE(split_channel(10'000, {}, 0).empty());
}

TEST(SplitChannelTest, TheGrantsNeverExceedTheChannel) {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> bps(0, 50'000);
    std::uniform_int_distribution<int> ttl_s(1, 20);
    std::uniform_int_distribution<int> count(0, 4);
    for (int run = 0; run < 1000; ++run) {
        ChannelDemands demands;
        for (int r = 0; r < 1 + run % 8; ++r) {
            auto& classes = demands["rover" + std::to_string(r)];
            for (int c = count(random); c > 0; --c)
                classes.push_back({std::chrono::seconds(ttl_s(random)), bps(random)});
        }
        const double capacity = bps(random);
        const ChannelGrants grants = split_channel(capacity, demands, 1'000);
        ASSERT_EQ(grants.size(), demands.size());
        EXPECT_LE(total(grants), capacity * (1 + 1e-9)) << "run " << run;
        for (const auto& [robot, g] : grants)
            EXPECT_GE(g, 0) << robot;
    }
}

class ChannelSharesTest : public ::testing::Test {
  protected:
    test::FakeClock clock_;
    ChannelShares shares_{ChannelShares::Config{5s, 1'000}, clock_};
};

TEST_F(ChannelSharesTest, GrantsFollowTheLatestDemands) {
    shares_.set_capacity(30'000);
    shares_.report("rover1", {{A_TTL, 20'000}});
    shares_.report("rover2", {{D_TTL, 40'000}});
    EXPECT_DOUBLE_EQ(shares_.grants().at("rover1"), 20'000);
    clock_.advance(1s);
    // rover1's hazards are past; rover2's D now has the channel, bar rover1's floor.
    shares_.report("rover1", {});
    const ChannelGrants grants = shares_.grants();
    EXPECT_DOUBLE_EQ(grants.at("rover1"), 1'000);
    EXPECT_DOUBLE_EQ(grants.at("rover2"), 29'000);
}

TEST_F(ChannelSharesTest, ARobotNotHeardFromLeavesItsShareToTheOthers) {
    shares_.set_capacity(30'000);
    shares_.report("rover1", {{A_TTL, 10'000}});
    shares_.report("rover2", {{A_TTL, 10'000}});
    clock_.advance(4s);
    shares_.report("rover2", {{A_TTL, 10'000}});
    EXPECT_EQ(shares_.grants().size(), 2u);
    clock_.advance(2s);  // rover1 last reported 6 s ago: stopped, restarted, or out of range
    const ChannelGrants grants = shares_.grants();
    EXPECT_EQ(grants.count("rover1"), 0u);
    EXPECT_DOUBLE_EQ(grants.at("rover2"), 30'000);
    // It comes back with its next report.
    shares_.report("rover1", {{A_TTL, 10'000}});
    EXPECT_DOUBLE_EQ(shares_.grants().at("rover1"), 15'000);
}

// A robot on a slow share reports seldom (its gateway's status takes a small part of its rate).
TEST_F(ChannelSharesTest, AReportMayHoldLongerThanTheDefault) {
    shares_.set_capacity(30'000);
    shares_.report("slow", {{A_TTL, 10'000}}, 60s);
    shares_.report("fast", {{A_TTL, 10'000}});
    clock_.advance(30s);
    const ChannelGrants grants = shares_.grants();
    EXPECT_EQ(grants.count("fast"), 0u);
    EXPECT_DOUBLE_EQ(grants.at("slow"), 30'000);
    clock_.advance(31s);
    EXPECT_TRUE(shares_.grants().empty());
}

// A robot's gateway restarted: the old gateway's share goes at once, not when it would go stale.
TEST_F(ChannelSharesTest, AForgottenRobotLeavesItsShareAtOnce) {
    shares_.set_capacity(30'000);
    shares_.report("old gateway", {{A_TTL, 10'000}}, 60s);
    shares_.report("other", {{A_TTL, 10'000}});
    shares_.forget("old gateway");
    const ChannelGrants grants = shares_.grants();
    EXPECT_EQ(grants.count("old gateway"), 0u);
    EXPECT_DOUBLE_EQ(grants.at("other"), 30'000);
}

// rover1's base camp sends it 12,000 bit/s of commands on the same channel: they take the air whatever the grants
// say, so rover1's grant carries them on top of its floor, before any robot's telemetry.
TEST_F(ChannelSharesTest, WhatTheCampSendsARobotIsInItsGrantBeforeAnyTelemetry) {
    shares_.set_capacity(30'000);
    shares_.report("rover1", {{A_TTL, 10'000}});
    shares_.report("rover2", {{D_TTL, 40'000}});
    shares_.set_camp_traffic("rover1", {200ms, 12'000});
    ChannelGrants grants = shares_.grants();
    // Floors 13,000 (1,000 and the commands) and 1,000; then rover1's A, 9,000 more; rover2 the 7,000 left.
    EXPECT_DOUBLE_EQ(grants.at("rover1"), 12'000 + 10'000);
    EXPECT_DOUBLE_EQ(grants.at("rover2"), 8'000);
    // Even where the telemetry's demand alone would fill the channel.
    shares_.report("rover2", {{A_TTL, 40'000}});
    grants = shares_.grants();
    EXPECT_GE(grants.at("rover1"), 12'000 + 1'000);
    EXPECT_LE(grants.at("rover1") + grants.at("rover2"), 30'000 * (1 + 1e-9));
    // The commands stopped.
    shares_.set_camp_traffic("rover1", {200ms, 0});
    shares_.report("rover2", {{D_TTL, 40'000}});
    EXPECT_DOUBLE_EQ(shares_.grants().at("rover1"), 10'000);
}

TEST_F(ChannelSharesTest, WhatTheCampSendsKeepsNoShareForARobotNotHeardFrom) {
    shares_.set_capacity(30'000);
    shares_.set_camp_traffic("unknown", {200ms, 12'000});
    shares_.report("rover2", {{D_TTL, 40'000}});
    EXPECT_EQ(shares_.grants().count("unknown"), 0u);
    shares_.report("rover1", {{A_TTL, 10'000}});
    shares_.set_camp_traffic("rover1", {200ms, 12'000});
    clock_.advance(6s);
    shares_.report("rover2", {{D_TTL, 40'000}});
    const ChannelGrants grants = shares_.grants();
    EXPECT_EQ(grants.count("rover1"), 0u);
    EXPECT_DOUBLE_EQ(grants.at("rover2"), 30'000);
}

TEST_F(ChannelSharesTest, NothingIsGrantedBeforeTheChannelIsMeasured) {
    shares_.report("rover1", {{A_TTL, 10'000}});
    EXPECT_TRUE(shares_.grants().empty());
}

}  // namespace
}  // namespace tgw::core
