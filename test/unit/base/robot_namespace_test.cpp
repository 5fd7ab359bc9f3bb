#include "base/robot_namespace.hpp"

#include <gtest/gtest.h>

namespace tgw::base {
namespace {

TEST(RobotNamespaceTest, Ros2TopicsGetTheNameAfterTheirPrefix) {
    EXPECT_EQ(namespaced_topic("rover1", "rt/chatter"), "rt/rover1/chatter");
    EXPECT_EQ(namespaced_topic("rover1", "rt/tf_static"), "rt/rover1/tf_static");
    EXPECT_EQ(namespaced_topic("rover1", "rt/camera/image_raw"), "rt/rover1/camera/image_raw");
}

TEST(RobotNamespaceTest, Ros2ServicesGetTheNameAfterTheirPrefix) {
    EXPECT_EQ(namespaced_topic("rover1", "rq/set_modeRequest"), "rq/rover1/set_modeRequest");
    EXPECT_EQ(namespaced_topic("rover1", "rr/set_modeReply"), "rr/rover1/set_modeReply");
}

TEST(RobotNamespaceTest, OtherTopicsGetTheNameInFront) {
    EXPECT_EQ(namespaced_topic("rover1", "telemetry/A"), "rover1/telemetry/A");
    EXPECT_EQ(namespaced_topic("rover1", "hazard"), "rover1/hazard");
    // Not a ROS 2 prefix: only rt/, rq/ and rr/ are.
    EXPECT_EQ(namespaced_topic("rover1", "rtk/fix"), "rover1/rtk/fix");
    EXPECT_EQ(namespaced_topic("rover1", "rt/"), "rover1/rt/");
}

TEST(RobotNamespaceTest, NoNameLeavesTheTopicAsItIs) {
    EXPECT_EQ(namespaced_topic("", "rt/chatter"), "rt/chatter");
    EXPECT_EQ(namespaced_topic("", "telemetry/A"), "telemetry/A");
}

TEST(RobotNamespaceTest, AcceptsRos2NamespaceTokens) {
    EXPECT_EQ(robot_name_problem("rover1"), "");
    EXPECT_EQ(robot_name_problem("Rover_2"), "");
    EXPECT_EQ(robot_name_problem("_spare"), "");
    EXPECT_EQ(robot_name_problem(std::string(64, 'r')), "");
}

TEST(RobotNamespaceTest, RefusesWhatIsNoRos2NamespaceTokenSayingWhy) {
    EXPECT_EQ(robot_name_problem(""), "is empty");
    EXPECT_EQ(robot_name_problem("1rover"), "starts with a digit");
    EXPECT_NE(robot_name_problem("rover/1").find("'/'"), std::string::npos);
    EXPECT_NE(robot_name_problem("rover-1").find("'-'"), std::string::npos);
    EXPECT_NE(robot_name_problem("rover 1").find("' '"), std::string::npos);
    EXPECT_EQ(robot_name_problem(std::string(65, 'r')), "is longer than 64 characters");
}

}  // namespace
}  // namespace tgw::base
