#include "sensor/delivered_rate_estimator.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "base/config_error.hpp"
#include "test/fakes/fake_clock.hpp"

namespace tgw::sensor {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr double CLAIM = 40'000.0;  // what the sensor says, bit/s: 5,000 B/s

/// Scripted counters of a link that carries `delivered` B/s while the gateway offers `sent` B/s, one sample a
/// second unless told otherwise.
class DeliveredRateEstimatorTest : public ::testing::Test {
  protected:
    /// Advances the clock, adds to the counters and feeds the sample.
    double step(std::uint64_t sent_bytes, std::uint64_t tx_bytes, std::uint64_t new_drops, std::uint64_t backlog,
                base::Duration after = seconds(1)) {
        clock.advance(after);
        counters.gateway_sent_bytes += sent_bytes;
        counters.tx_bytes += tx_bytes;
        counters.drops += new_drops;
        counters.backlog_bytes = backlog;
        return sut.update(counters, CLAIM);
    }
    /// A second in which the link carries all the gateway sends at `rate_bps`.
    double clear_second(double rate_bps) {
        const auto bytes = static_cast<std::uint64_t>(rate_bps / 8.0);
        return step(bytes, bytes, 0, 0);
    }

    test::FakeClock clock;
    DeliveredRateConfig config;
    DeliveredRateEstimator sut{config, clock};
    LinkCounters counters;
};

TEST_F(DeliveredRateEstimatorTest, PassesTheClaimOnWhileTheLinkDelivers) {
    EXPECT_EQ(sut.update(counters, CLAIM), CLAIM);
    EXPECT_EQ(sut.verdict(), LinkVerdict::unknown);
    EXPECT_EQ(clear_second(CLAIM), CLAIM);
    EXPECT_EQ(sut.verdict(), LinkVerdict::delivering);
    EXPECT_EQ(sut.delivered_bps(), CLAIM);
    EXPECT_FALSE(sut.cap_bps());
}

TEST_F(DeliveredRateEstimatorTest, CutsTheBudgetWhenTheQdiscDrops) {
    sut.update(counters, CLAIM);
    EXPECT_DOUBLE_EQ(step(5'000, 4'000, 3, 1'000), 0.8 * CLAIM);
    EXPECT_EQ(sut.verdict(), LinkVerdict::congested);
    EXPECT_DOUBLE_EQ(sut.delivered_bps().value(), 32'000.0);
}

TEST_F(DeliveredRateEstimatorTest, CutsTheBudgetWhenTheBacklogIsLongAndGrowing) {
    sut.update(counters, CLAIM);
    // 250 ms at 40 kbit/s drain 1,250 B; the floor of 3,028 B rules here.
    EXPECT_EQ(step(5'000, 4'000, 0, 3'000), CLAIM);
    EXPECT_DOUBLE_EQ(step(5'000, 4'000, 0, 4'000), 0.8 * CLAIM);
    EXPECT_EQ(sut.verdict(), LinkVerdict::congested);
}

TEST_F(DeliveredRateEstimatorTest, WaitsWhileALongBacklogDrains) {
    sut.update(counters, CLAIM);
    step(5'000, 4'000, 0, 6'000);
    const double cut = 0.8 * CLAIM;
    EXPECT_DOUBLE_EQ(step(3'000, 4'000, 0, 5'000), cut);
    EXPECT_EQ(sut.verdict(), LinkVerdict::draining);
    EXPECT_DOUBLE_EQ(step(3'000, 4'000, 0, 4'000), cut);
}

TEST_F(DeliveredRateEstimatorTest, CutsAtMostOncePerDecreaseInterval) {
    sut.update(counters, CLAIM);
    EXPECT_DOUBLE_EQ(step(500, 400, 1, 0, milliseconds(100)), 0.8 * CLAIM);
    for (int i = 0; i < 9; ++i)
        EXPECT_DOUBLE_EQ(step(500, 400, 1, 0, milliseconds(100)), 0.8 * CLAIM) << i;
    EXPECT_DOUBLE_EQ(step(500, 400, 1, 0, milliseconds(100)), 0.64 * CLAIM);
}

TEST_F(DeliveredRateEstimatorTest, KeepsCuttingWhileDropsPersist) {
    sut.update(counters, CLAIM);
    double budget = CLAIM;
    for (int i = 0; i < 3; ++i)
        budget = step(5'000, 2'500, 2, 2'000);
    EXPECT_DOUBLE_EQ(budget, 0.8 * 0.8 * 0.8 * CLAIM);
}

TEST_F(DeliveredRateEstimatorTest, PersistentCongestionStopsAtWhatTheLinkCarries) {
    // Someone else keeps the link full: it carries 20,000 bit/s and drops every second, whatever the gateway does.
    sut.update(counters, CLAIM);
    double budget = CLAIM;
    for (int i = 0; i < 10; ++i)
        budget = step(2'500, 2'500, 4, 2'000);
    EXPECT_DOUBLE_EQ(budget, 0.8 * 20'000.0);  // 32,000, 25,600, 20,480, 16,384, then 80 % of the 20,000 carried
}

TEST_F(DeliveredRateEstimatorTest, MeasuresTheDeliveredRateOverAWholeWindow) {
    sut.update(counters, CLAIM);
    // A shaper passes one 1,210 B frame in a 100 ms poll and nothing in the next nine: 9,680 bit/s, not 96,800.
    step(1'210, 1'210, 0, 0, milliseconds(100));
    EXPECT_FALSE(sut.delivered_bps());
    for (int i = 0; i < 9; ++i)
        step(0, 0, 0, 0, milliseconds(100));
    EXPECT_NEAR(sut.delivered_bps().value(), 9'680.0, 1e-6);
}

TEST_F(DeliveredRateEstimatorTest, NeverCutsBelowTheMinimumFraction) {
    sut.update(counters, CLAIM);
    double budget = CLAIM;
    for (int i = 0; i < 30; ++i)
        budget = step(5'000, 100, 5, 9'000);
    EXPECT_DOUBLE_EQ(budget, 0.1 * CLAIM);
}

TEST_F(DeliveredRateEstimatorTest, RaisesTheCapAdditivelyOnceDropsStopAndLiftsItAtTheClaim) {
    sut.update(counters, CLAIM);
    step(5'000, 4'000, 1, 0);  // cap 32,000
    ASSERT_DOUBLE_EQ(sut.cap_bps().value(), 32'000.0);
    // +2 % of the claim (800 bit/s) per second of clear sending at the cap.
    EXPECT_DOUBLE_EQ(clear_second(32'000.0), 32'800.0);
    EXPECT_DOUBLE_EQ(clear_second(32'800.0), 33'600.0);
    double budget = 0.0;
    for (int i = 0; i < 8; ++i)
        budget = clear_second(budget == 0.0 ? 33'600.0 : budget);
    EXPECT_EQ(budget, CLAIM);
    EXPECT_FALSE(sut.cap_bps());
}

TEST_F(DeliveredRateEstimatorTest, DoesNotRaiseTheCapWhileTheGatewayIsIdle) {
    sut.update(counters, CLAIM);
    step(5'000, 4'000, 1, 0);
    for (int i = 0; i < 5; ++i)
        EXPECT_DOUBLE_EQ(clear_second(1'000.0), 32'000.0) << i;
}

TEST_F(DeliveredRateEstimatorTest, FollowsAClaimBelowTheCapAndDropsACapAboveIt) {
    sut.update(counters, CLAIM);
    step(5'000, 4'000, 1, 0);  // cap 32,000
    clock.advance(seconds(1));
    counters.gateway_sent_bytes += 2'000;
    counters.tx_bytes += 2'000;
    EXPECT_EQ(sut.update(counters, 16'000.0), 16'000.0);
    EXPECT_FALSE(sut.cap_bps());
}

TEST_F(DeliveredRateEstimatorTest, StartsAfreshWhenCountersReset) {
    sut.update(counters, CLAIM);
    step(5'000, 5'000, 0, 0);
    counters = LinkCounters{};  // the interface was re-created
    clock.advance(seconds(1));
    EXPECT_EQ(sut.update(counters, CLAIM), CLAIM);
    EXPECT_EQ(sut.verdict(), LinkVerdict::delivering);  // unchanged: no interval measured across the reset
    EXPECT_EQ(step(5'000, 5'000, 0, 0), CLAIM);
}

TEST_F(DeliveredRateEstimatorTest, IgnoresASampleAtTheSameInstant) {
    sut.update(counters, CLAIM);
    counters.drops += 5;
    EXPECT_EQ(sut.update(counters, CLAIM), CLAIM);
    EXPECT_EQ(sut.verdict(), LinkVerdict::unknown);
}

TEST_F(DeliveredRateEstimatorTest, GivesNothingForAnInvalidClaim) {
    EXPECT_EQ(sut.update(counters, -1.0), 0.0);
    EXPECT_EQ(sut.update(counters, std::nan("")), 0.0);
}

TEST_F(DeliveredRateEstimatorTest, RefusesAnInvalidConfigNamingTheField) {
    const auto error_of = [this](DeliveredRateConfig bad) {
        try {
            DeliveredRateEstimator estimator(bad, clock);
        } catch (const base::ConfigError& e) {
            return std::string(e.what());
        }
        return std::string("<no error>");
    };
    DeliveredRateConfig bad;
    bad.decrease_factor = 1.0;
    EXPECT_EQ(error_of(bad), "delivered-rate check: decrease_factor must be in (0, 1)");
    bad = DeliveredRateConfig{};
    bad.min_cap_fraction = 0.0;
    EXPECT_EQ(error_of(bad), "delivered-rate check: min_cap_fraction must be in (0, 1]");
    bad = DeliveredRateConfig{};
    bad.max_queue_delay = base::Duration::zero();
    EXPECT_EQ(error_of(bad), "delivered-rate check: max_queue_delay must be above 0");
    EXPECT_EQ(DeliveredRateConfig{}.validate(), "");
}

}  // namespace
}  // namespace tgw::sensor
