// RateCap: a topic's max_rate_hz, as a token bucket that takes a publisher at the cap whole despite its jitter.
#include "core/rate_cap.hpp"

#include <gtest/gtest.h>

namespace tgw::core {
namespace {

using std::chrono::milliseconds;

base::SteadyTime at(int ms) {
    return base::SteadyTime(milliseconds(ms));
}

int admitted_of(RateCap& cap, int samples, int period_ms, int jitter_ms = 0) {
    int admitted = 0;
    for (int i = 0; i < samples; ++i) {
        const int jitter = (i % 2 == 0) ? jitter_ms : -jitter_ms;
        admitted += cap.admit(at(1000 + i * period_ms + jitter)) ? 1 : 0;
    }
    return admitted;
}

TEST(RateCapTest, AFasterPublisherIsThinnedToTheCap) {
    RateCap cap(5.0);
    // 30 Hz for 10 s: 300 samples, at most 5 a second pass.
    const int admitted = admitted_of(cap, 300, 33);
    EXPECT_GE(admitted, 49);
    EXPECT_LE(admitted, 51);
}

TEST(RateCapTest, APublisherAtTheCapPassesWholeDespiteJitter) {
    RateCap cap(5.0);
    // 200 ms apart, each 8 ms early or late: intervals of 184 and 216 ms.
    EXPECT_EQ(admitted_of(cap, 100, 200, 8), 100);
}

TEST(RateCapTest, ASlowerPublisherPassesWhole) {
    RateCap cap(10.0);
    EXPECT_EQ(admitted_of(cap, 50, 250), 50);
}

TEST(RateCapTest, APauseSavesUpNoBurst) {
    RateCap cap(2.0);
    EXPECT_TRUE(cap.admit(at(0)));
    // Ten seconds of nothing, then a burst: one passes, the next only after most of a period.
    EXPECT_TRUE(cap.admit(at(10'000)));
    EXPECT_FALSE(cap.admit(at(10'001)));
    EXPECT_FALSE(cap.admit(at(10'400)));
    EXPECT_TRUE(cap.admit(at(10'460)));
}

TEST(RateCapTest, AClockStepBackAdmitsNothingExtra) {
    RateCap cap(1.0);
    EXPECT_TRUE(cap.admit(at(5'000)));
    EXPECT_FALSE(cap.admit(at(4'000)));
    EXPECT_FALSE(cap.admit(at(5'500)));
    EXPECT_TRUE(cap.admit(at(6'000)));
}

}  // namespace
}  // namespace tgw::core
