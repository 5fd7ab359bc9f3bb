// tm-basecamp report's grants: the rounds the relay recorded (SampleStore's SQLite file), per robot.
#include "basecamp/analysis/grant_summary.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "basecamp/recording/sample_store.hpp"
#include "test/unit/basecamp/recording_file.hpp"
#include "test/unit/basecamp/scratch_dir.hpp"

namespace tgw::basecamp {
namespace {

constexpr std::int64_t T0_NS = 1'800'000'000'000'000'000;
constexpr std::int64_t S = 1'000'000'000;

ChannelRecord round(std::int64_t at_s, double channel_bps, std::vector<GrantRecord> grants) {
    ChannelRecord c;
    c.time_ns = T0_NS + at_s * S;
    c.channel_bps = channel_bps;
    c.newcomer_bps = 0.1 * channel_bps;
    c.grants = std::move(grants);
    return c;
}

class GrantSummaryTest : public ::testing::Test {
  protected:
    test::ScratchDir dir_{"tgw-grants"};
    const std::string recording_ = dir_.file("camp.db");
};

TEST_F(GrantSummaryTest, EachRobotsGrantsOverTheRecordingUnderItsName) {
    {
        SampleStore store(recording_, "--out", 10);
        store.add_channel(round(0, 60'000, {{"aa01", "rover1", 27'000}, {"aa02", "rover2", 27'000}}));
        store.add_channel(round(1, 60'000, {{"aa01", "rover1", 40'000}, {"aa02", "rover2", 14'000}}));
        // rover2's gateway restarted: a new prefix, the same robot; a gateway without a name under its prefix.
        store.add_channel(
            round(2, 50'000, {{"aa01", "rover1", 30'000}, {"bb02", "rover2", 9'000}, {"cc03", "", 6'000}}));
        store.flush();
    }
    const std::optional<GrantSummary> summary = read_grant_summary(recording_);
    ASSERT_TRUE(summary);
    EXPECT_EQ(summary->rounds, 3u);
    EXPECT_FALSE(summary->measured);
    EXPECT_DOUBLE_EQ(summary->min_channel_bps, 50'000);
    EXPECT_DOUBLE_EQ(summary->max_channel_bps, 60'000);
    EXPECT_NEAR(summary->mean_channel_bps, 170'000.0 / 3, 1e-6);
    ASSERT_EQ(summary->robots.size(), 3u);
    const RobotGrants& unnamed = summary->robots[0];
    EXPECT_EQ(unnamed.robot, "cc03");
    EXPECT_EQ(unnamed.rounds, 1u);
    const RobotGrants& rover1 = summary->robots[1];
    EXPECT_EQ(rover1.robot, "rover1");
    EXPECT_EQ(rover1.rounds, 3u);
    EXPECT_DOUBLE_EQ(rover1.min_bps, 27'000);
    EXPECT_NEAR(rover1.mean_bps, 97'000.0 / 3, 1e-6);
    EXPECT_DOUBLE_EQ(rover1.max_bps, 40'000);
    EXPECT_DOUBLE_EQ(rover1.last_bps, 30'000);
    const RobotGrants& rover2 = summary->robots[2];
    EXPECT_EQ(rover2.rounds, 3u) << "both of its gateways";
    EXPECT_DOUBLE_EQ(rover2.last_bps, 9'000);

    std::ostringstream out;
    print_grant_summary(out, *summary);
    EXPECT_NE(out.str().find("3 rounds, 56667 bit/s on average (50000 to 60000)"), std::string::npos) << out.str();
    EXPECT_NE(out.str().find("rover1                      3      27000      32333      40000      30000"),
              std::string::npos)
        << out.str();
}

TEST_F(GrantSummaryTest, AMeasuredChannelSaysSo) {
    {
        SampleStore store(recording_, "--out", 10);
        ChannelRecord c = round(0, 30'000, {{"aa01", "rover1", 27'000}});
        c.verdict = "clear";
        c.delivered_bps = 20'000;
        c.queueing_ns = 0;
        store.add_channel(c);
        store.flush();
    }
    const std::optional<GrantSummary> summary = read_grant_summary(recording_);
    ASSERT_TRUE(summary);
    EXPECT_TRUE(summary->measured);
}

TEST_F(GrantSummaryTest, ARecordingWithoutGrantsHasNoSummary) {
    test::write_recording(recording_, {}, {});
    EXPECT_FALSE(read_grant_summary(recording_));
}

}  // namespace
}  // namespace tgw::basecamp
