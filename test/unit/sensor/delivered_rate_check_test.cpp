#include "sensor/delivered_rate_check.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "base/config_error.hpp"
#include "test/fakes/fake_clock.hpp"
#include "test/fakes/scripted_sensor.hpp"

namespace tgw::sensor {
namespace {

using std::chrono::seconds;

constexpr double CLAIM = 40'000.0;  // what the sensor says, bit/s

/// A DeliveredRateCheck over a scripted sensor that always claims CLAIM, and kernel counters the test sets.
class DeliveredRateCheckTest : public ::testing::Test {
  protected:
    DeliveredRateCheckTest() {
        auto inner = std::make_unique<test::ScriptedSensor>("fixed:40000");
        inner->then_rate(CLAIM, "inner detail");
        sensor = inner.get();
        DeliveredRateSources sources;
        sources.kernel = [this] { return kernel; };
        sources.sent_bytes = [this] { return sent_bytes; };
        sut = std::make_unique<DeliveredRateCheck>(std::move(inner), std::move(sources), DeliveredRateConfig{}, clock,
                                                   [this](SensorLogLevel level, const std::string& message) {
                                                       messages.push_back({level, message});
                                                   });
        kernel.ok = true;
    }

    /// One second in which the gateway sent `sent` bytes and the interface `tx`, the qdisc dropped `drops`
    /// packets and holds `backlog` bytes at its end.
    RateReading second(std::uint64_t sent, std::uint64_t tx, std::uint64_t drops, std::uint64_t backlog) {
        clock.advance(seconds(1));
        sent_bytes += sent;
        kernel.counters.tx_bytes += tx;
        kernel.counters.drops += drops;
        kernel.counters.backlog_bytes = backlog;
        return sut->read();
    }

    test::FakeClock clock;
    test::ScriptedSensor* sensor = nullptr;
    KernelCountersReading kernel;
    std::uint64_t sent_bytes = 0;
    std::vector<std::pair<SensorLogLevel, std::string>> messages;
    std::unique_ptr<DeliveredRateCheck> sut;
};

TEST_F(DeliveredRateCheckTest, PassesTheSensorsRateWhileTheLinkDelivers) {
    EXPECT_EQ(sut->read().rate_bps, CLAIM);
    const RateReading r = second(5'000, 5'000, 0, 0);
    EXPECT_TRUE(r.ok);
    EXPECT_EQ(r.rate_bps, CLAIM);
    EXPECT_EQ(r.detail, "inner detail; link delivering, delivered 40000 bit/s");
    EXPECT_EQ(r.queued_bytes, 0u);
    EXPECT_FALSE(r.cap_bps);
    EXPECT_TRUE(messages.empty());
    EXPECT_EQ(sut->describe(), "fixed:40000+delivered-check");
}

TEST_F(DeliveredRateCheckTest, CapsTheRateWhileTheQdiscDropsAndLogsOnce) {
    sut->read();
    const RateReading first = second(5'000, 4'000, 3, 1'500);
    EXPECT_DOUBLE_EQ(first.rate_bps, 0.8 * CLAIM);
    EXPECT_EQ(first.queued_bytes, 1'500u);  // the fixed sensor has no view of the queue: the check gives it
    EXPECT_NE(first.detail.find("capped at 32000 bit/s"), std::string::npos) << first.detail;
    EXPECT_EQ(first.cap_bps, 32'000.0);
    EXPECT_DOUBLE_EQ(second(4'000, 4'000, 2, 1'500).rate_bps, 0.64 * CLAIM);
    ASSERT_EQ(messages.size(), 1u);
    EXPECT_EQ(messages[0].first, SensorLogLevel::warning);
    EXPECT_NE(messages[0].second.find("budget capped at 32000 bit/s"), std::string::npos) << messages[0].second;
}

TEST_F(DeliveredRateCheckTest, LiftsTheCapOnceTheLinkCarriesTheClaimAgainAndSaysSo) {
    sut->read();
    second(5'000, 4'000, 3, 1'500);
    ASSERT_TRUE(sut->cap_bps());
    // 2 % of the claim back per congestion-free second while the gateway uses the cap: 20 % takes 10 s.
    int seconds_to_lift = 0;
    while (sut->cap_bps() && seconds_to_lift < 60) {
        second(4'000, 4'000, 0, 0);
        ++seconds_to_lift;
    }
    EXPECT_EQ(seconds_to_lift, 10);
    EXPECT_EQ(sut->read().rate_bps, CLAIM);
    ASSERT_EQ(messages.size(), 2u);
    EXPECT_EQ(messages[1].first, SensorLogLevel::info);
    EXPECT_NE(messages[1].second.find("cap lifted"), std::string::npos);
}

TEST_F(DeliveredRateCheckTest, AnIdleLinkDoesNotEarnTheCapBack) {
    sut->read();
    second(5'000, 4'000, 3, 1'500);
    const double cap = sut->cap_bps().value();
    for (int i = 0; i < 30; ++i)
        second(100, 100, 0, 0);  // the gateway had nothing to send
    EXPECT_DOUBLE_EQ(sut->cap_bps().value(), cap);
}

TEST_F(DeliveredRateCheckTest, KeepsTheSensorsOwnViewOfTheQueue) {
    RateReading with_backlog;
    with_backlog.ok = true;
    with_backlog.rate_bps = CLAIM;
    with_backlog.queued_bytes = 700;
    sut->read();
    sensor->then(with_backlog);
    kernel.counters.backlog_bytes = 9'000;
    EXPECT_EQ(sut->read().queued_bytes, 700u);
}

TEST_F(DeliveredRateCheckTest, FailingCountersPassTheRateThroughAndAreLoggedOncePerEpisode) {
    sut->read();
    second(5'000, 4'000, 3, 1'500);
    kernel = KernelCountersReading{};
    kernel.error = "no interface veth-x: Object not found";
    const RateReading r = second(0, 0, 0, 0);
    EXPECT_TRUE(r.ok);
    EXPECT_EQ(r.rate_bps, CLAIM);  // the cap needs counters to stand on
    second(0, 0, 0, 0);
    second(0, 0, 0, 0);
    kernel.ok = true;
    kernel.error.clear();
    second(0, 0, 0, 0);
    ASSERT_EQ(messages.size(), 3u);  // cap, failure start, failure end
    EXPECT_NE(messages[1].second.find("no interface veth-x"), std::string::npos);
    EXPECT_NE(messages[2].second.find("over: no interface veth-x"), std::string::npos);
    EXPECT_NE(messages[2].second.find("checking the sensor's rate again"), std::string::npos);
}

TEST_F(DeliveredRateCheckTest, AFailedSensorReadingIsPassedOnUntouched) {
    sut->read();
    sensor->then_fail("netlink timeout");
    const RateReading r = sut->read();
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.error, "netlink timeout");
}

TEST_F(DeliveredRateCheckTest, WithoutTheGatewaysCountTheInterfacesTransmitCounterStandsIn) {
    DeliveredRateSources sources;
    sources.kernel = [this] { return kernel; };
    auto inner = std::make_unique<test::ScriptedSensor>();
    inner->then_rate(CLAIM);
    DeliveredRateCheck check(std::move(inner), std::move(sources), {}, clock, {});
    const auto tick = [&](std::uint64_t tx, std::uint64_t drops) {
        clock.advance(seconds(1));
        kernel.counters.tx_bytes += tx;
        kernel.counters.drops += drops;
        return check.read().rate_bps;
    };
    check.read();
    EXPECT_DOUBLE_EQ(tick(4'000, 3), 32'000.0);
    EXPECT_DOUBLE_EQ(tick(100, 0), 32'000.0);          // little went out: an idle link proves nothing
    EXPECT_DOUBLE_EQ(tick(4'000, 0), 32'000.0 + 800);  // the link carried the cap: 2 % of the claim back
}

TEST(DeliveredRateCheck, RefusesToStartWithoutKernelCounters) {
    test::FakeClock clock;
    EXPECT_THROW(DeliveredRateCheck(std::make_unique<test::ScriptedSensor>(), {}, {}, clock, {}), base::ConfigError);
}

TEST(DeliveredRateCheck, KernelSourcesNameAMissingInterface) {
    try {
        kernel_sources("tgw-no-such-if0", {});
        FAIL() << "expected a ConfigError";
    } catch (const base::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("tgw-no-such-if0"), std::string::npos) << e.what();
    }
}

TEST(DeliveredRateCheck, KernelSourcesReadLoopbacksCounters) {
    const DeliveredRateSources sources = kernel_sources("lo", {});
    const KernelCountersReading reading = sources.kernel();
    EXPECT_TRUE(reading.ok) << reading.error;
}

}  // namespace
}  // namespace tgw::sensor
