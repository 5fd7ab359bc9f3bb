#include "gateway/dds/topic_filter.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace tgw::dds
