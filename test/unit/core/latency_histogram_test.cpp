#include "core/latency_histogram.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <thread>
#include <vector>

namespace tgw::core {
namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;

class LatencyHistogramTest : public ::testing::Test {
  protected:
    /// True when `got` is within the histogram's resolution (1/32 of the value, rounded up) of `want`.
    static bool close(base::Duration got, base::Duration want) {
        const auto tolerance = want.count() / 32 + 1;
        return std::abs(got.count() - want.count()) <= tolerance;
    }

    LatencyHistogram sut;
};

TEST_F(LatencyHistogramTest, ReportsZeroWhenNothingWasRecorded) {
    const auto s = sut.snapshot();
    EXPECT_EQ(s.count, 0u);
    EXPECT_EQ(s.median(), base::Duration::zero());
    EXPECT_EQ(s.percentile(0.99), base::Duration::zero());
    EXPECT_EQ(s.mean(), base::Duration::zero());
}

TEST_F(LatencyHistogramTest, CountsSmallValuesExactly) {
    for (int ns = 0; ns < 16; ++ns) {
        sut.record(nanoseconds(ns));
    }
    const auto s = sut.snapshot();
    EXPECT_EQ(s.count, 16u);
    EXPECT_EQ(s.percentile(1.0 / 16), nanoseconds(0));
    EXPECT_EQ(s.median(), nanoseconds(7));
    EXPECT_EQ(s.percentile(1.0), nanoseconds(15));
}

TEST_F(LatencyHistogramTest, BucketsAreContiguousAndCoverEveryValue) {
    for (std::size_t b = 0; b + 1 < LatencyHistogram::BUCKET_COUNT; ++b) {
        const std::uint64_t lower = LatencyHistogram::bucket_lower_ns(b);
        const std::uint64_t upper = LatencyHistogram::bucket_upper_ns(b);
        ASSERT_LT(lower, upper) << b;
        ASSERT_EQ(upper, LatencyHistogram::bucket_lower_ns(b + 1)) << b;
        ASSERT_EQ(LatencyHistogram::bucket_of(lower), b) << b;
        ASSERT_EQ(LatencyHistogram::bucket_of(upper - 1), b) << b;
        // Resolution: a bucket is at most 1/16 of its lower bound wide.
        ASSERT_LE(upper - lower, std::max<std::uint64_t>(1, lower / 16)) << b;
    }
    EXPECT_EQ(LatencyHistogram::bucket_of(UINT64_MAX), LatencyHistogram::BUCKET_COUNT - 1);
}

TEST_F(LatencyHistogramTest, PercentilesOfAUniformSpreadAreWithinResolution) {
    for (int us = 1; us <= 1000; ++us) {
        sut.record(microseconds(us));
    }
    const auto s = sut.snapshot();
    EXPECT_EQ(s.count, 1000u);
    EXPECT_TRUE(close(s.median(), microseconds(500))) << s.median().count();
    EXPECT_TRUE(close(s.percentile(0.9), microseconds(900))) << s.percentile(0.9).count();
    EXPECT_TRUE(close(s.percentile(0.99), microseconds(990))) << s.percentile(0.99).count();
    EXPECT_EQ(s.percentile(1.0), microseconds(1000));
    EXPECT_EQ(s.mean(), nanoseconds(500'500));
}

TEST_F(LatencyHistogramTest, AnOutlierMovesTheMaximumButNotTheMedian) {
    for (int i = 0; i < 99; ++i) {
        sut.record(microseconds(10));
    }
    sut.record(milliseconds(10));
    const auto s = sut.snapshot();
    EXPECT_TRUE(close(s.median(), microseconds(10)));
    EXPECT_TRUE(close(s.percentile(0.99), microseconds(10)));
    EXPECT_EQ(s.max, milliseconds(10));
    EXPECT_EQ(s.percentile(1.0), milliseconds(10));
}

TEST_F(LatencyHistogramTest, PercentileNeverExceedsTheMaximum) {
    // The lower bound of a bucket 32,768 ns wide: its midpoint lies above every sample.
    sut.record(nanoseconds(983'040));
    sut.record(nanoseconds(983'040));
    EXPECT_EQ(sut.snapshot().median(), nanoseconds(983'040));
}

TEST_F(LatencyHistogramTest, CountsANegativeLatencyAsZero) {
    sut.record(nanoseconds(-5));
    const auto s = sut.snapshot();
    EXPECT_EQ(s.count, 1u);
    EXPECT_EQ(s.median(), base::Duration::zero());
}

TEST_F(LatencyHistogramTest, SinceLeavesOutWhatWasRecordedBefore) {
    for (int i = 0; i < 50; ++i) {
        sut.record(milliseconds(5));
    }
    const auto warm_up = sut.snapshot();
    for (int i = 0; i < 10; ++i) {
        sut.record(microseconds(20));
    }
    const auto s = sut.snapshot().since(warm_up);
    EXPECT_EQ(s.count, 10u);
    EXPECT_TRUE(close(s.percentile(1.0), microseconds(20))) << s.percentile(1.0).count();
    EXPECT_TRUE(close(s.max, microseconds(20))) << s.max.count();
    EXPECT_EQ(s.mean(), microseconds(20));
}

TEST_F(LatencyHistogramTest, SinceAnIdenticalSnapshotIsEmpty) {
    sut.record(microseconds(3));
    const auto s = sut.snapshot();
    const auto none = s.since(s);
    EXPECT_EQ(none.count, 0u);
    EXPECT_EQ(none.median(), base::Duration::zero());
}

TEST_F(LatencyHistogramTest, CountsEveryRecordFromConcurrentThreads) {
    constexpr int THREADS = 4;
    constexpr int PER_THREAD = 50'000;
    std::vector<std::thread> threads;
    for (int t = 0; t < THREADS; ++t) {
        threads.emplace_back([this, t] {
            for (int i = 0; i < PER_THREAD; ++i) {
                sut.record(nanoseconds(100 * (t + 1)));
            }
        });
    }
    for (auto& thread : threads) {
        thread.join();
    }
    const auto s = sut.snapshot();
    EXPECT_EQ(s.count, static_cast<std::uint64_t>(THREADS * PER_THREAD));
    EXPECT_EQ(s.max, nanoseconds(100 * THREADS));
    EXPECT_EQ(s.sum, nanoseconds(std::int64_t{100} * PER_THREAD * (THREADS * (THREADS + 1) / 2)));
}

}  // namespace
}  // namespace tgw::core
