#include "basecamp/live/status_view.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "basecamp/status/gateway_status.hpp"
#include "test/unit/basecamp/status_samples.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {
namespace {

constexpr std::int64_t S = 1'000'000'000;
constexpr std::int64_t T0 = 1'700'000'000 * S;

SampleRecord status_at(std::int64_t sent_ns, double rate_bps, std::uint8_t gateway = 1) {
    idl::GatewayStatus status;
    status.gateway_prefix()[0] = gateway;
    status.sent_ns(static_cast<std::uint64_t>(sent_ns));
    status.sensed_rate_bps(rate_bps);
    status.sensor("qdisc:veth0");
    status.topics().push_back(test::topic_status("telemetry/A", 1000, 150, 2));
    SampleRecord r;
    r.topic = wire::STATUS_TOPIC;
    r.receive_ns = sent_ns + S / 10;
    r.source_ns = sent_ns;
    r.payload = test::serialized(status);
    return r;
}

class StatusViewTest : public ::testing::Test {
  protected:
    StatusView sut{std::chrono::minutes(1)};
};

TEST_F(StatusViewTest, DrawsTheRateOfTheLastMinutesAndTheLatestCountsPerTopic) {
    // 20,000 bit/s for 30 s, then 10,000 for 30 s, a status every 10 s.
    for (int i = 0; i <= 6; ++i) {
        sut.add(status_at(T0 + i * 10 * S, i < 3 ? 20'000 : 10'000));
    }
    EXPECT_EQ(sut.statuses(), 7u);
    std::ostringstream out;
    sut.render(out, T0 + 61 * S, 6);
    const std::string screen = out.str();
    EXPECT_NE(screen.find("sensor qdisc:veth0"), std::string::npos) << screen;
    // One column per 10 s: the oldest status fell out of the minute; then 20,000 twice, 10,000 four times.
    EXPECT_NE(screen.find("|██▅▅▅▅|"), std::string::npos) << screen;
    EXPECT_NE(screen.find("telemetry/A"), std::string::npos) << screen;
    std::istringstream lines(screen);
    std::string line;
    while (std::getline(lines, line) && line.find("  telemetry/A") != 0) {
    }
    std::istringstream fields(line);
    std::vector<std::string> f{std::istream_iterator<std::string>(fields), std::istream_iterator<std::string>()};
    ASSERT_GE(f.size(), 7u) << line;
    EXPECT_EQ(f[4], "152") << "received";
    EXPECT_EQ(f[5], "150") << "forwarded";
    EXPECT_EQ(f[6], "2") << "expired";
}

TEST_F(StatusViewTest, KeepsEachGatewayApartAndCountsMalformedSamples) {
    sut.add(status_at(T0, 20'000, 1));
    sut.add(status_at(T0, 30'000, 2));
    SampleRecord bad = status_at(T0, 1);
    bad.payload.resize(7);
    sut.add(bad);
    EXPECT_EQ(sut.statuses(), 2u);
    EXPECT_EQ(sut.malformed(), 1u);
    std::ostringstream out;
    sut.render(out, T0 + S);
    EXPECT_NE(out.str().find("gateway 01."), std::string::npos);
    EXPECT_NE(out.str().find("gateway 02."), std::string::npos);
}

TEST_F(StatusViewTest, SaysWhenTheDeliveredRateCheckCapsTheRate) {
    SampleRecord capped = status_at(T0, 15'000);
    idl::GatewayStatus status = *decode_gateway_status(capped.payload);
    status.delivered_cap_bps(15'000);
    capped.payload = test::serialized(status);
    sut.add(status_at(T0 - 10 * S, 26'000));
    std::ostringstream before;
    sut.render(before, T0);
    EXPECT_EQ(before.str().find("(capped at"), std::string::npos) << before.str();
    sut.add(capped);
    std::ostringstream after;
    sut.render(after, T0 + S);
    EXPECT_NE(after.str().find("sensed 15000 bit/s (capped at 15000 by the delivered-rate check)"), std::string::npos)
        << after.str();
}

TEST_F(StatusViewTest, ShowsTheBackfillBacklogOnlyWhereThereIsOne) {
    sut.add(status_at(T0 - S, 26'000));
    std::ostringstream without;
    sut.render(without, T0 - S);
    EXPECT_EQ(without.str().find("backfill"), std::string::npos) << without.str();
    SampleRecord backfilling = status_at(T0, 26'000);
    idl::GatewayStatus status = *decode_gateway_status(backfilling.payload);
    status.backfill_rows(120);
    status.backfill_bytes(90'000);
    status.backfill_oldest_ns(T0 - 95 * S);
    status.backfill_sent(40);
    status.backfill_acknowledged(35);
    backfilling.payload = test::serialized(status);
    sut.add(backfilling);
    std::ostringstream with;
    sut.render(with, T0);
    EXPECT_NE(with.str().find("backfill: 120 rows not yet in the camp's archive (90000 B, the oldest 95 s old); 40 "
                              "sent, 35 acknowledged"),
              std::string::npos)
        << with.str();
}

TEST_F(StatusViewTest, ShowsBackfillsRateAndWhenTheBacklogClearsAtIt) {
    // Every 10 s, 25 more rows acknowledged and 25 fewer left: 2.5 rows/s.
    for (int i = 0; i <= 4; ++i) {
        SampleRecord backfilling = status_at(T0 + i * 10 * S, 26'000);
        idl::GatewayStatus status = *decode_gateway_status(backfilling.payload);
        status.backfill_rows(static_cast<unsigned long long>(200 - 25 * i));
        status.backfill_sent(static_cast<unsigned long long>(30 * i));
        status.backfill_acknowledged(static_cast<unsigned long long>(25 * i));
        backfilling.payload = test::serialized(status);
        sut.add(backfilling);
    }
    std::ostringstream out;
    sut.render(out, T0 + 40 * S);
    EXPECT_NE(out.str().find("backfill's rate: 2.5 rows/s acknowledged over the last 30 s; the backlog clears in "
                             "about 40 s at it"),
              std::string::npos)
        << out.str();
}

TEST(SparklineTest, ScalesFromTheLowestToTheHighestBlockAndLeavesGapsBlank) {
    EXPECT_EQ(sparkline({0.0, 50.0, 100.0, std::nullopt, 200.0}, 100.0), "▁▅█ █");
}

}  // namespace
}  // namespace tgw::basecamp
