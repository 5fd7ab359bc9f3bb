#include "sensor/trace_sensor.hpp"

#include <gtest/gtest.h>

#include "test/fakes/fake_clock.hpp"

namespace tgw::sensor {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

class TraceSensorTest : public ::testing::Test {
  protected:
    test::FakeClock clock;
    TraceSensor sut{RateTrace({{seconds(0), 20'000.0}, {seconds(10), 5'000.0}, {seconds(20), 0.0}}), "link.trace",
                    clock};
};

TEST_F(TraceSensorTest, ReadsTheFirstRateAtConstruction) {
    const RateReading reading = sut.read();
    EXPECT_TRUE(reading.ok);
    EXPECT_EQ(reading.rate_bps, 20'000.0);
}

TEST_F(TraceSensorTest, FollowsTheStepsAsTheClockAdvances) {
    clock.advance(milliseconds(9'999));
    EXPECT_EQ(sut.read().rate_bps, 20'000.0);
    clock.advance(milliseconds(1));
    EXPECT_EQ(sut.read().rate_bps, 5'000.0);
    clock.advance(seconds(10));
    const RateReading outage = sut.read();
    EXPECT_TRUE(outage.ok);
    EXPECT_EQ(outage.rate_bps, 0.0);
}

TEST_F(TraceSensorTest, HoldsTheLastRateAfterTheTraceEnds) {
    clock.advance(std::chrono::hours(24));
    EXPECT_EQ(sut.read().rate_bps, 0.0);
}

TEST_F(TraceSensorTest, MeasuresTimeFromItsOwnConstruction) {
    clock.advance(seconds(15));
    TraceSensor later(RateTrace({{seconds(0), 1.0}, {seconds(10), 2.0}}), "other.trace", clock);
    EXPECT_EQ(later.read().rate_bps, 1.0);
    clock.advance(seconds(10));
    EXPECT_EQ(later.read().rate_bps, 2.0);
}

TEST_F(TraceSensorTest, DescribesItselfAsASpec) {
    EXPECT_EQ(sut.describe(), "trace:link.trace");
}

}  // namespace
}  // namespace tgw::sensor
