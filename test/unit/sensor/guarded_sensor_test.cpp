#include "sensor/guarded_sensor.hpp"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "base/config_error.hpp"
#include "test/fakes/fake_clock.hpp"
#include "test/fakes/scripted_sensor.hpp"

namespace tgw::sensor {
namespace {

using std::chrono::seconds;

class GuardedSensorTest : public ::testing::Test {
  protected:
    GuardedSensorTest() {
        config.hold = seconds(5);
        config.floor_bps = 8'000.0;
        config.smoothing = 0.5;
        config.margin = 0.1;
    }

    /// Builds the guard over `script`, which the test keeps a handle on.
    GuardedSensor make(test::ScriptedSensor*& script) {
        auto owned = std::make_unique<test::ScriptedSensor>("qdisc:wan0");
        script = owned.get();
        return GuardedSensor(std::move(owned), config, clock,
                             [this](SensorLogLevel level, const std::string& m) { logged.emplace_back(level, m); });
    }

    /// One poll a second, as the gateway does.
    RateReading poll(GuardedSensor& sut) {
        const RateReading reading = sut.read();
        clock.advance(seconds(1));
        return reading;
    }

    test::FakeClock clock;
    GuardConfig config;
    std::vector<std::pair<SensorLogLevel, std::string>> logged;
    test::ScriptedSensor* script = nullptr;
};

TEST_F(GuardedSensorTest, PassesAGoodReadingOnLessTheMargin) {
    GuardedSensor sut = make(script);
    script->then_rate(20'000.0, "tbf");
    const RateReading reading = poll(sut);
    ASSERT_TRUE(reading.ok);
    EXPECT_DOUBLE_EQ(reading.rate_bps, 18'000.0);
    EXPECT_EQ(reading.detail, "tbf, sensed 20000 bit/s");
    EXPECT_EQ(sut.state(), GuardState::tracking);
    EXPECT_EQ(sut.describe(), "qdisc:wan0");
    EXPECT_TRUE(logged.empty());
}

TEST_F(GuardedSensorTest, FollowsAFallingRateAtOnce) {
    GuardedSensor sut = make(script);
    script->then_rate(40'000.0).then_rate(10'000.0);
    poll(sut);
    EXPECT_DOUBLE_EQ(poll(sut).rate_bps, 9'000.0);
}

TEST_F(GuardedSensorTest, SmoothsARisingRate) {
    GuardedSensor sut = make(script);
    script->then_rate(10'000.0).then_rate(30'000.0).then_rate(30'000.0);
    poll(sut);
    EXPECT_DOUBLE_EQ(poll(sut).rate_bps, 0.9 * 20'000.0);
    EXPECT_DOUBLE_EQ(poll(sut).rate_bps, 0.9 * 25'000.0);
}

TEST_F(GuardedSensorTest, PassesQueuedBytesOnFromAGoodReading) {
    GuardedSensor sut = make(script);
    RateReading raw;
    raw.ok = true;
    raw.rate_bps = 20'000.0;
    raw.queued_bytes = 1'500;
    script->then(raw);
    EXPECT_EQ(poll(sut).queued_bytes, 1'500u);
}

TEST_F(GuardedSensorTest, HoldsTheLastGoodRateThenFallsBackToTheFloor) {
    GuardedSensor sut = make(script);
    script->then_rate(20'000.0).then_fail("no interface wan0");
    poll(sut);  // t = 0, good
    for (int t = 1; t <= 5; ++t) {
        const RateReading reading = poll(sut);
        ASSERT_TRUE(reading.ok);
        EXPECT_DOUBLE_EQ(reading.rate_bps, 18'000.0) << "t = " << t;
        EXPECT_EQ(reading.detail, "holding last good (no interface wan0)");
        EXPECT_EQ(sut.state(), GuardState::holding);
    }
    const RateReading reading = poll(sut);  // t = 6: 6 s since the good reading
    EXPECT_DOUBLE_EQ(reading.rate_bps, 8'000.0);
    EXPECT_EQ(reading.detail, "floor (no interface wan0)");
    EXPECT_EQ(sut.state(), GuardState::floor);
}

TEST_F(GuardedSensorTest, UsesTheFloorBeforeAnyGoodReading) {
    GuardedSensor sut = make(script);
    script->then_fail("station 02:00:00:00:01:00 on wlan0 reports no transmit bit rate");
    const RateReading reading = poll(sut);
    EXPECT_TRUE(reading.ok);
    EXPECT_EQ(reading.rate_bps, 8'000.0);
    EXPECT_EQ(sut.state(), GuardState::floor);
}

TEST_F(GuardedSensorTest, LogsAFailureOnceWhenItStartsAndOnceWhenItEnds) {
    GuardedSensor sut = make(script);
    script->then_rate(20'000.0);
    for (int i = 0; i < 3; ++i)
        script->then_fail("cannot list the stations of wlan0: timeout");
    script->then_rate(20'000.0).then_rate(20'000.0);
    for (int i = 0; i < 6; ++i)
        poll(sut);
    ASSERT_EQ(logged.size(), 2u);
    EXPECT_EQ(logged[0].first, SensorLogLevel::warning);
    EXPECT_EQ(logged[0].second,
              "sensor qdisc:wan0: reading failed: cannot list the stations of wlan0: timeout; holding the last good "
              "rate for up to 4 s");
    EXPECT_EQ(logged[1].first, SensorLogLevel::info);
    EXPECT_EQ(logged[1].second,
              "sensor qdisc:wan0: failure ended after 3 s: cannot list the stations of wlan0: timeout");
}

TEST_F(GuardedSensorTest, TreatsErrorsThatDifferOnlyInNumbersAsOneFailure) {
    GuardedSensor sut = make(script);
    script->then_fail("link quality 5 of wlan0 is below the table's lowest row")
        .then_fail("link quality 4 of wlan0 is below the table's lowest row")
        .then_fail("link quality 12 of wlan0 is below the table's lowest row");
    for (int i = 0; i < 3; ++i)
        poll(sut);
    ASSERT_EQ(logged.size(), 1u);
    EXPECT_EQ(logged[0].second,
              "sensor qdisc:wan0: reading failed: link quality 5 of wlan0 is below the table's lowest row; using the "
              "floor rate 8000 bit/s");
}

TEST_F(GuardedSensorTest, LogsTheEndOfOneKindAndTheStartOfTheNext) {
    GuardedSensor sut = make(script);
    script->then_rate(20'000.0).then_fail("no interface wan0").then_fail("wan0 has no root qdisc, so no shaper");
    for (int i = 0; i < 3; ++i)
        poll(sut);
    ASSERT_EQ(logged.size(), 3u);
    EXPECT_EQ(logged[1].first, SensorLogLevel::info);
    EXPECT_EQ(logged[1].second, "sensor qdisc:wan0: failure ended after 1 s: no interface wan0");
    EXPECT_EQ(logged[2].first, SensorLogLevel::warning);
    EXPECT_EQ(logged[2].second.rfind("sensor qdisc:wan0: reading failed: wan0 has no root qdisc", 0), 0u);
    EXPECT_EQ(sut.state(), GuardState::holding);  // still within the hold of the last good reading
}

TEST_F(GuardedSensorTest, LogsOnceWhenTheHoldRunsOut) {
    GuardedSensor sut = make(script);
    script->then_rate(20'000.0).then_fail("no interface wan0");
    for (int i = 0; i < 10; ++i)
        poll(sut);
    ASSERT_EQ(logged.size(), 2u);
    EXPECT_EQ(logged[1].first, SensorLogLevel::warning);
    EXPECT_EQ(logged[1].second, "sensor qdisc:wan0: no good reading for 6 s; using the floor rate 8000 bit/s");
}

TEST_F(GuardedSensorTest, StartsTheAverageAfreshAfterTheFloor) {
    GuardedSensor sut = make(script);
    script->then_rate(10'000.0);
    for (int i = 0; i < 7; ++i)
        script->then_fail("no interface wan0");
    script->then_rate(30'000.0);
    for (int i = 0; i < 8; ++i)
        poll(sut);
    EXPECT_EQ(sut.state(), GuardState::floor);
    EXPECT_DOUBLE_EQ(poll(sut).rate_bps, 27'000.0);
    EXPECT_EQ(sut.state(), GuardState::tracking);
}

TEST_F(GuardedSensorTest, TreatsAnInvalidRateAsAFailure) {
    GuardedSensor sut = make(script);
    script->then_rate(-5.0);
    const RateReading reading = poll(sut);
    EXPECT_EQ(reading.rate_bps, 8'000.0);
    EXPECT_EQ(sut.state(), GuardState::floor);
    ASSERT_EQ(logged.size(), 1u);
}

TEST_F(GuardedSensorTest, WorksWithoutALog) {
    GuardedSensor sut(std::make_unique<test::ScriptedSensor>(), config, clock, nullptr);
    EXPECT_EQ(sut.read().rate_bps, 8'000.0);
}

TEST_F(GuardedSensorTest, RefusesAnInvalidConfigNamingTheField) {
    const auto error_of = [this](GuardConfig bad) {
        try {
            GuardedSensor sut(std::make_unique<test::ScriptedSensor>("fixed:20k"), bad, clock, nullptr);
        } catch (const base::ConfigError& e) {
            return std::string(e.what());
        }
        return std::string("<no error>");
    };
    GuardConfig bad = config;
    bad.margin = 1.0;
    EXPECT_EQ(error_of(bad), "sensor fixed:20k: margin must be in [0, 1)");
    bad = config;
    bad.smoothing = 0.0;
    EXPECT_EQ(error_of(bad), "sensor fixed:20k: smoothing must be in (0, 1]");
    bad = config;
    bad.floor_bps = -1.0;
    EXPECT_EQ(error_of(bad), "sensor fixed:20k: floor_bps must be a rate >= 0 bit/s");
    bad = config;
    bad.hold = seconds(-1);
    EXPECT_EQ(error_of(bad), "sensor fixed:20k: hold must not be negative");
    EXPECT_EQ(GuardConfig{}.validate(), "");
}

}  // namespace
}  // namespace tgw::sensor
