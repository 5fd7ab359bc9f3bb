// IntroductionSchedule: when the WAN participant announces itself again to a participant that has not answered.
#include <gtest/gtest.h>

#include <chrono>

#include "gateway/dds/introduction_schedule.hpp"

namespace tgw::dds {
namespace {

using namespace std::chrono_literals;

const IntroductionSchedule::Prefix CAMP{1, 2, 3};
const IntroductionSchedule::Prefix OTHER{4, 5, 6};

base::SteadyTime at(base::Duration d) {
    return base::SteadyTime{} + d;
}

TEST(IntroductionScheduleTest, AnnouncesAgainAtOneTwoAndFourSecondsWhileUnanswered) {
    IntroductionSchedule sut;
    EXPECT_FALSE(sut.next_due());
    sut.discovered(CAMP, at(10s));
    EXPECT_EQ(sut.next_due(), at(11s));
    EXPECT_FALSE(sut.take_due(at(10s) + 999ms));
    EXPECT_TRUE(sut.take_due(at(11s)));
    EXPECT_FALSE(sut.take_due(at(11s))) << "each time is due once";
    EXPECT_EQ(sut.next_due(), at(12s));
    EXPECT_TRUE(sut.take_due(at(12s)));
    EXPECT_EQ(sut.next_due(), at(14s));
    EXPECT_TRUE(sut.take_due(at(14s)));
    EXPECT_FALSE(sut.next_due()) << "then the periodic announcement is left to do it";
    EXPECT_EQ(sut.waiting(), 0u);
}

TEST(IntroductionScheduleTest, StopsOnceTheParticipantAnswersOrLeaves) {
    IntroductionSchedule sut;
    sut.discovered(CAMP, at(0s));
    sut.discovered(OTHER, at(0s));
    EXPECT_TRUE(sut.take_due(at(1s)));
    sut.answered(CAMP);
    sut.removed(OTHER);
    EXPECT_FALSE(sut.next_due());
    EXPECT_FALSE(sut.take_due(at(10s)));
}

TEST(IntroductionScheduleTest, TimesThatPassedTogetherMakeOneAnnouncement) {
    IntroductionSchedule sut;
    sut.discovered(CAMP, at(0s));
    sut.discovered(OTHER, at(500ms));
    EXPECT_TRUE(sut.take_due(at(3s))) << "CAMP's 1 s and 2 s, OTHER's 1.5 s and 2.5 s: one announcement";
    EXPECT_EQ(sut.next_due(), at(4s));
    EXPECT_TRUE(sut.take_due(at(4s)));
    EXPECT_EQ(sut.waiting(), 1u);
    EXPECT_EQ(sut.next_due(), at(4500ms));
}

TEST(IntroductionScheduleTest, ADiscoveryAgainStartsOver) {
    IntroductionSchedule sut;
    sut.discovered(CAMP, at(0s));
    EXPECT_TRUE(sut.take_due(at(5s)));
    EXPECT_EQ(sut.waiting(), 0u);
    sut.discovered(CAMP, at(100s));  // it left and came back with the same prefix
    EXPECT_EQ(sut.next_due(), at(101s));
}

}  // namespace
}  // namespace tgw::dds
