#include "gateway/log/default_log_path.hpp"

#include <gtest/gtest.h>

namespace tgw::log {
namespace {

TEST(DefaultLogPathTest, IsInTheXdgStateDirectory) {
    EXPECT_EQ(default_log_path("/var/lib/robot", "/home/op"), "/var/lib/robot/telemetry-gateway/robot-log.db");
}

TEST(DefaultLogPathTest, FallsBackToTheHomesStateDirectory) {
    EXPECT_EQ(default_log_path(nullptr, "/root"), "/root/.local/state/telemetry-gateway/robot-log.db");
    EXPECT_EQ(default_log_path("", "/root"), "/root/.local/state/telemetry-gateway/robot-log.db");
}

TEST(DefaultLogPathTest, IgnoresARelativeStateDirectoryAsTheSpecAsks) {
    EXPECT_EQ(default_log_path("state", "/home/op"), "/home/op/.local/state/telemetry-gateway/robot-log.db");
}

TEST(DefaultLogPathTest, WithoutEitherIsInTheWorkingDirectory) {
    EXPECT_EQ(default_log_path(nullptr, nullptr), "robot-log.db");
}

}  // namespace
}  // namespace tgw::log
