#include "sensor/receiver_report_source.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <utility>

#include "sensor/delivered_rate_check.hpp"
#include "test/fakes/fake_clock.hpp"
#include "test/fakes/scripted_sensor.hpp"

namespace tgw::sensor {
namespace {

KernelCountersReading kernel_reading(std::uint64_t tx, std::uint64_t drops, std::uint64_t backlog) {
    KernelCountersReading r;
    r.ok = true;
    r.counters = {tx, drops, backlog};
    return r;
}

TEST(WithReceiverReports, AddsReportedLossesToTheQdiscsDrops) {
    const CounterSource source = with_receiver_reports([] { return kernel_reading(10'000, 3, 500); },
                                                       [] {
                                                           return std::optional<ReceiverCounts>({9'000, 4, 700});
                                                       });
    const KernelCountersReading r = source();
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(r.counters.tx_bytes, 10'000u);  // the interface's own counter wins
    EXPECT_EQ(r.counters.drops, 3u + 4u);
    EXPECT_EQ(r.counters.backlog_bytes, 700u);  // the queue on the whole way, the larger
}

TEST(WithReceiverReports, WithoutAReportTheKernelReadsAsItIs) {
    const CounterSource source = with_receiver_reports([] { return kernel_reading(10'000, 3, 0); },
                                                       [] { return std::optional<ReceiverCounts>(); });
    EXPECT_EQ(source().counters.drops, 3u);
}

TEST(WithReceiverReports, AloneTheReportsStandForTheInterface) {
    const CounterSource source = with_receiver_reports({}, [] {
        return std::optional<ReceiverCounts>({9'000, 4, 700});
    });
    const KernelCountersReading r = source();
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(r.counters.tx_bytes, 9'000u);
    EXPECT_EQ(r.counters.drops, 4u);
    EXPECT_EQ(r.counters.backlog_bytes, 700u);
}

TEST(WithReceiverReports, AloneAndBeforeTheFirstReportItFailsNamingTheCause) {
    const CounterSource source = with_receiver_reports({}, [] { return std::optional<ReceiverCounts>(); });
    const KernelCountersReading r = source();
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("no receiver report yet"), std::string::npos) << r.error;
}

/// A DeliveredRateCheck over a sensor claiming `claim` bit/s whose counters come from receiver reports the test
/// sets, alone or beside an interface that sends all it is given and neither drops nor queues.
class ReportedCheckTest : public ::testing::Test {
  protected:
    void start(double claim, bool with_interface) {
        auto inner = std::make_unique<test::ScriptedSensor>("fixed");
        inner->then_rate(claim, "");
        DeliveredRateSources sources;
        CounterSource kernel;
        if (with_interface) {
            kernel = [this] { return kernel_reading(sent, 0, 0); };
        }
        sources.kernel = with_receiver_reports(kernel, [this] { return std::optional<ReceiverCounts>(received); });
        sources.sent_bytes = [this] { return sent; };
        check = std::make_unique<DeliveredRateCheck>(std::move(inner), std::move(sources), DeliveredRateConfig{}, clock,
                                                     SensorLog{});
        EXPECT_EQ(check->read().rate_bps, claim);
    }

    test::FakeClock clock;
    std::uint64_t sent = 0;
    ReceiverCounts received;
    std::unique_ptr<DeliveredRateCheck> check;
};

TEST_F(ReportedCheckTest, AQueuePastThisHostCapsTheBudget) {
    // Nothing lost, but what was sent and neither received nor lost grows to 4 kB: 1.6 s of queue at 20 kbit/s.
    start(20'000.0, false);
    for (std::uint64_t in_flight : {2'000u, 4'000u}) {
        clock.advance(std::chrono::seconds(1));
        sent += 2'500;
        received.received_wire_bytes = sent - in_flight;
        received.in_flight_bytes = in_flight;
    }
    const RateReading r = check->read();
    EXPECT_LT(r.rate_bps, 20'000.0);
    EXPECT_EQ(r.queued_bytes, received.in_flight_bytes);  // the scheduler waits for the queue to drain
}

TEST_F(ReportedCheckTest, LossesPastThisHostCapTheBudget) {
    // The interface sends all the gateway gives it, but the receiver reports losses: a bottleneck further on.
    // The check must cut as it would for qdisc drops.
    start(40'000.0, true);
    clock.advance(std::chrono::seconds(1));
    sent += 5'000;
    received.received_wire_bytes += 4'000;
    received.lost_samples += 5;
    EXPECT_DOUBLE_EQ(check->read().rate_bps, 0.8 * 40'000.0);
    EXPECT_EQ(check->verdict(), LinkVerdict::congested);
}

}  // namespace
}  // namespace tgw::sensor
