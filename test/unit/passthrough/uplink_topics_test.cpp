#include "passthrough/uplink_topics.hpp"

#include <gtest/gtest.h>

#include "base/config_error.hpp"

namespace tgw::passthrough {
namespace {

using namespace std::chrono_literals;

TEST(UplinkTopicsTest, ARobotsCommandsComeUnderItsNameOnTheWan) {
    const UplinkTopics topics({"rt/cmd_vel", "arm/goal"}, "rover1");
    EXPECT_EQ(topics.robot_topic("rt/rover1/cmd_vel"), "rt/cmd_vel");
    EXPECT_EQ(topics.robot_topic("rover1/arm/goal"), "arm/goal");
    // Another robot's commands, and the robot's own name on the WAN, are not this robot's.
    EXPECT_EQ(topics.robot_topic("rt/rover2/cmd_vel"), std::nullopt);
    EXPECT_EQ(topics.robot_topic("rt/cmd_vel"), std::nullopt);
}

TEST(UplinkTopicsTest, WithoutARobotNameTheNamesAreTheSame) {
    const UplinkTopics topics({"rt/cmd_vel", "rt/cmd_vel"}, "");
    EXPECT_EQ(topics.robot_topic("rt/cmd_vel"), "rt/cmd_vel");
    EXPECT_EQ(topics.robot_topic("rt/cmd_vel2"), std::nullopt);
    EXPECT_FALSE(topics.empty());
    EXPECT_TRUE(UplinkTopics({}, "rover1").empty());
}

TEST(UplinkTopicsTest, RefusesPatternsAndEmptyNamesNamingTheFlag) {
    for (const char* bad : {"", "rt/*", "rt/cmd_vel?", "rt/[ab]"}) {
        try {
            UplinkTopics({"rt/ok", bad}, "");
            ADD_FAILURE() << "'" << bad << "' was taken";
        } catch (const base::ConfigError& e) {
            EXPECT_EQ(std::string(e.what()).rfind("--uplink", 0), 0u) << e.what();
        }
    }
}

TEST(UplinkTopicsTest, ACommandAtOrPastItsDeadlineIsExpired) {
    const base::WallTime sent = base::wall_from_ns(1'000'000'000'000);
    EXPECT_FALSE(uplink_expired(sent, 200ms, sent));
    EXPECT_FALSE(uplink_expired(sent, 200ms, sent + 199ms));
    EXPECT_TRUE(uplink_expired(sent, 200ms, sent + 200ms));
    EXPECT_TRUE(uplink_expired(sent, 200ms, sent + 5s));
    // Stamped ahead of the robot's clock: fresh until its deadline on the robot's clock.
    EXPECT_FALSE(uplink_expired(sent + 1s, 200ms, sent));
}

}  // namespace
}  // namespace tgw::passthrough
