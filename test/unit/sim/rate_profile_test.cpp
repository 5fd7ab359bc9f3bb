#include "gateway/sim/rate_profile.hpp"

#include <gtest/gtest.h>

namespace tgw::sim {
namespace {

using base::Duration;
using std::chrono::milliseconds;
using std::chrono::seconds;

class RateProfileTest : public ::testing::Test {
  protected:
    // 10 kbit/s for 10 s, an outage of 5 s, then 20 kbit/s.
    RateProfile sut{{{seconds(0), 10'000}, {seconds(10), 0}, {seconds(15), 20'000}}};
};

TEST_F(RateProfileTest, RateHoldsFromItsStepUntilTheNext) {
    EXPECT_EQ(sut.rate_at(seconds(0)), 10'000);
    EXPECT_EQ(sut.rate_at(milliseconds(9'999)), 10'000);
    EXPECT_EQ(sut.rate_at(seconds(10)), 0);
    EXPECT_EQ(sut.rate_at(seconds(100)), 20'000);
}

TEST_F(RateProfileTest, FirstRateHoldsBeforeTheFirstStep) {
    RateProfile late_start({{seconds(5), 1'000}});
    EXPECT_EQ(late_start.rate_at(seconds(1)), 1'000);
}

TEST_F(RateProfileTest, NextChangeIsTheFollowingStep) {
    EXPECT_EQ(sut.next_change_after(seconds(3)), seconds(10));
    EXPECT_EQ(sut.next_change_after(seconds(10)), seconds(15));
    EXPECT_EQ(sut.next_change_after(seconds(15)), Duration::max());
}

TEST_F(RateProfileTest, TransmissionWithinOneStepTakesBitsOverRate) {
    EXPECT_EQ(sut.finish_offset(seconds(1), 10'000), seconds(2));
}

TEST_F(RateProfileTest, TransmissionPausesThroughAnOutage) {
    // 5,000 bits before the outage at 10 kbit/s, the other 10,000 after it at 20 kbit/s.
    EXPECT_EQ(sut.finish_offset(milliseconds(9'500), 15'000), milliseconds(15'500));
}

TEST_F(RateProfileTest, ALinkThatNeverComesBackNeverFinishes) {
    RateProfile dead({{seconds(0), 1'000}, {seconds(1), 0}});
    EXPECT_EQ(dead.finish_offset(seconds(0), 5'000), Duration::max());
}

}  // namespace
}  // namespace tgw::sim
