#include "gateway/sim/simulated_link.hpp"

#include <gtest/gtest.h>

namespace tgw::sim {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr std::uint64_t BITS_PER_BYTE = 8;

/// The testbed's default shaper: tbf rate 20000bit burst 1600 latency 1000ms.
class SimulatedLinkTest : public ::testing::Test {
  protected:
    static std::uint64_t bytes(std::uint64_t n) { return n * BITS_PER_BYTE; }

    base::SteadyTime t0{std::chrono::hours(1)};
    SimulatedLink sut{RateProfile::constant(20'000), t0, seconds(1), 1600};
};

TEST_F(SimulatedLinkTest, ABurstPassesAtOnceAfterAnIdleSpell) {
    EXPECT_EQ(*sut.send(t0, bytes(500)), t0);
    EXPECT_EQ(*sut.send(t0, bytes(500)), t0);
    EXPECT_EQ(*sut.send(t0, bytes(500)), t0);
    // 100 bytes left in the bucket; the other 400 take 160 ms at 2,500 bytes/s.
    EXPECT_EQ(*sut.send(t0, bytes(500)), t0 + milliseconds(160));
    // After a second of idle link the bucket is full again.
    EXPECT_EQ(*sut.send(t0 + seconds(2), bytes(1'500)), t0 + seconds(2));
}

TEST_F(SimulatedLinkTest, PacketsLeaveAtTheRateOnceTheBucketIsEmpty) {
    EXPECT_EQ(*sut.send(t0, bytes(1'600)), t0);
    for (int k = 1; k <= 10; ++k) {
        EXPECT_EQ(*sut.send(t0, bytes(250)), t0 + milliseconds(100) * k);
    }
}

TEST_F(SimulatedLinkTest, TheBucketFillsOnlyUpToTheBurst) {
    sut.send(t0, bytes(1'600));
    // Ten idle seconds still buy only 1,600 bytes at once.
    EXPECT_EQ(*sut.send(t0 + seconds(10), bytes(1'600)), t0 + seconds(10));
    EXPECT_EQ(*sut.send(t0 + seconds(10), bytes(250)), t0 + seconds(10) + milliseconds(100));
}

TEST_F(SimulatedLinkTest, TheQueueHoldsRateTimesLatencyPlusTheBurstInBytes) {
    EXPECT_EQ(sut.queue_limit_bytes(t0), 2'500u + 1'600u);
}

TEST_F(SimulatedLinkTest, DropsAPacketThatDoesNotFitTheFullQueue) {
    sut.send(t0, bytes(1'600));  // empties the bucket and leaves at once
    std::optional<base::SteadyTime> last;
    for (int k = 0; k < 41; ++k) {
        last = sut.send(t0, bytes(100));
        ASSERT_TRUE(last) << "packet " << k;
    }
    // 4,100 bytes queued: the last of them waits 1.64 s, longer than the latency.
    EXPECT_EQ(*last, t0 + milliseconds(1'640));
    EXPECT_FALSE(sut.send(t0, bytes(100)));
    EXPECT_EQ(sut.dropped_bits(), bytes(100));
    // Once the head has left, there is room again.
    EXPECT_TRUE(sut.send(t0 + milliseconds(40), bytes(100)));
    EXPECT_EQ(sut.sent_bits(), bytes(1'600 + 42 * 100));
}

TEST_F(SimulatedLinkTest, ARateChangeRefillsTheBucketAndAppliesToTheQueue) {
    SimulatedLink link{RateProfile({{seconds(0), 20'000}, {seconds(1), 40'000}}), t0, seconds(1), 1600};
    link.send(t0, bytes(1'600));
    EXPECT_EQ(*link.send(t0, bytes(1'000)), t0 + milliseconds(400));
    EXPECT_EQ(*link.send(t0, bytes(1'000)), t0 + milliseconds(800));
    // Would leave at 1.2 s, but `tc qdisc change` at 1 s refills the bucket.
    EXPECT_EQ(*link.send(t0, bytes(1'000)), t0 + seconds(1));
    // 600 bytes left in the bucket, the other 400 at 5,000 bytes/s.
    EXPECT_EQ(*link.send(t0, bytes(1'000)), t0 + milliseconds(1'080));
    EXPECT_EQ(link.queue_limit_bytes(t0 + seconds(1)), 5'000u + 1'600u);
}

TEST_F(SimulatedLinkTest, AnOutageAtAVeryLowRateShrinksTheQueueToAboutTheBurst) {
    SimulatedLink link{RateProfile({{seconds(0), 20'000}, {seconds(1), 1'000}, {seconds(11), 20'000}}), t0, seconds(1),
                       1600};
    const base::SteadyTime outage = t0 + seconds(2);
    EXPECT_EQ(link.queue_limit_bytes(outage), 125u + 1'600u);
    EXPECT_EQ(*link.send(outage, bytes(1'600)), outage);  // the bucket, full since the change
    EXPECT_EQ(*link.send(outage, bytes(250)), outage + seconds(2));
    EXPECT_FALSE(link.send(outage, bytes(1'500)));  // 1,750 bytes would not fit 1,725
    // Would need 8 s at 1,000 bit/s; the rate comes back at 11 s with a full bucket.
    EXPECT_EQ(*link.send(outage, bytes(1'000)), t0 + seconds(11));
    EXPECT_EQ(link.dropped_bits(), bytes(1'500));
}

TEST_F(SimulatedLinkTest, ARateOfZeroThatNeverEndsCarriesNothingBeyondTheBucket) {
    SimulatedLink link{RateProfile({{seconds(0), 20'000}, {seconds(1), 0}}), t0, seconds(1), 1600};
    EXPECT_EQ(*link.send(t0 + seconds(2), bytes(1'600)), t0 + seconds(2));
    EXPECT_FALSE(link.send(t0 + seconds(2), bytes(100)));
    EXPECT_EQ(link.dropped_bits(), bytes(100));
}

TEST_F(SimulatedLinkTest, APacketLargerThanTheBucketWaitsForAFullBucketAndLeavesItInDebt) {
    EXPECT_EQ(*sut.send(t0, bytes(2'000)), t0);
    // 400 bytes of debt and 250 more: 260 ms.
    EXPECT_EQ(*sut.send(t0, bytes(250)), t0 + milliseconds(260));
}

}  // namespace
}  // namespace tgw::sim
