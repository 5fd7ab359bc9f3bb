#include "basecamp/live/topic_stats.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "test/unit/basecamp/status_samples.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {
namespace {

constexpr std::int64_t MS = 1'000'000;
constexpr std::int64_t S = 1'000 * MS;
constexpr std::int64_t T0 = 1'700'000'000 * S;

SampleRecord received(const std::string& topic, std::int64_t receive_ns, std::int64_t transmission_ns,
                      std::size_t bytes) {
    SampleRecord r;
    r.topic = topic;
    r.receive_ns = receive_ns;
    r.source_ns = receive_ns - transmission_ns;
    r.payload.assign(bytes, 0);
    return r;
}

TopicRecord topic_with_lifespan(const std::string& name, std::optional<std::int64_t> lifespan_ns) {
    TopicRecord t;
    t.topic = name;
    t.lifespan_ns = lifespan_ns;
    return t;
}

class TopicStatsTest : public ::testing::Test {
  protected:
    TopicStats sut{std::chrono::seconds(10)};
};

TEST_F(TopicStatsTest, ATenHertzTopicShowsItsRateBandwidthAndTransmissionTimes) {
    sut.add_topic(topic_with_lifespan("a", 1 * S));
    // 100 samples of 125 bytes at 10 Hz; 98 take 50 ms, two take 1.5 s (past the 1 s TTL).
    for (int i = 0; i < 100; ++i) {
        sut.add(received("a", T0 + i * 100 * MS, (i == 40 || i == 70) ? 1500 * MS : 50 * MS, 125));
    }
    const auto rows = sut.rows(T0 + 99 * 100 * MS);
    ASSERT_EQ(rows.size(), 1u);
    const TopicStatsRow& r = rows[0];
    EXPECT_EQ(r.total_samples, 100u);
    EXPECT_EQ(r.window_samples, 100u);
    EXPECT_NEAR(r.hz, 10.0, 1e-9);
    EXPECT_NEAR(r.bit_per_s, 100 * 125 * 8 / 9.9, 1e-6) << "100 samples over the 9.9 s since the first";
    EXPECT_NEAR(*r.mean_ms, (98 * 50.0 + 2 * 1500.0) / 100, 1e-9);
    EXPECT_NEAR(*r.p99_ms, 1500.0, 1e-9);
    EXPECT_DOUBLE_EQ(*r.ttl_s, 1.0);
    EXPECT_DOUBLE_EQ(*r.on_time_pct, 98.0);
    EXPECT_FALSE(r.logged_on_robot) << "no gateway status seen";
}

TEST_F(TopicStatsTest, OnlyTheWindowCounts) {
    for (int i = 0; i < 200; ++i) {  // 20 s at 10 Hz; then 5 s at 2 Hz
        sut.add(received("a", T0 + i * 100 * MS, 10 * MS, 100));
    }
    for (int i = 1; i <= 10; ++i) {
        sut.add(received("a", T0 + 20 * S + i * 500 * MS, 10 * MS, 100));
    }
    const TopicStatsRow r = sut.rows(T0 + 25 * S)[0];
    EXPECT_EQ(r.total_samples, 210u);
    // The window is 15 s to 25 s: 50 samples at 10 Hz, then 10 at 2 Hz.
    EXPECT_EQ(r.window_samples, 60u);
    EXPECT_NEAR(r.bit_per_s, 60 * 100 * 8 / 10.0, 1e-6);
    EXPECT_FALSE(r.on_time_pct) << "no TTL known";
}

TEST_F(TopicStatsTest, TheGatewaysStatusGivesWhatTheRobotLoggedAndTheTtl) {
    idl::GatewayStatus status;
    status.gateway_prefix()[0] = 1;
    status.topics().push_back(test::topic_status("a", 2000, 40, 3));
    SampleRecord s = received(wire::STATUS_TOPIC, T0, 5 * MS, 0);
    s.payload = test::serialized(status);
    sut.add(s);
    sut.add(received("a", T0, 2500 * MS, 10));
    sut.add(received("a", T0 + 100 * MS, 500 * MS, 10));

    const auto rows = sut.rows(T0 + 200 * MS);
    ASSERT_EQ(rows.size(), 2u);
    const TopicStatsRow& a = rows[0];
    EXPECT_EQ(a.topic, "a");
    EXPECT_EQ(a.logged_on_robot, 3u);
    EXPECT_DOUBLE_EQ(*a.ttl_s, 2.0) << "no Lifespan: the status's TTL";
    EXPECT_DOUBLE_EQ(*a.on_time_pct, 50.0);
    EXPECT_EQ(rows[1].topic, wire::STATUS_TOPIC);
}

TEST_F(TopicStatsTest, AMalformedStatusIsCountedAsASampleAndOtherwiseIgnored) {
    SampleRecord s = received(wire::STATUS_TOPIC, T0, 5 * MS, 0);
    s.payload = {0x00, 0x01, 0x00, 0x00, 0xff, 0xff, 0xff, 0xff, 0x01};
    sut.add(s);
    const auto rows = sut.rows(T0);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].total_samples, 1u);
}

TEST_F(TopicStatsTest, TheTableShowsADashForWhatIsUnknown) {
    sut.add(received("a", T0, 10 * MS, 100));
    std::ostringstream out;
    print_stats_table(out, sut.rows(T0 + S));
    EXPECT_NE(out.str().find("topic"), std::string::npos);
    std::istringstream lines(out.str());
    std::string header, row;
    std::getline(lines, header);
    std::getline(lines, row);
    std::istringstream fields(row);
    std::vector<std::string> f{std::istream_iterator<std::string>(fields), std::istream_iterator<std::string>()};
    ASSERT_EQ(f.size(), 9u) << row;
    EXPECT_EQ(f[0], "a");
    EXPECT_EQ(f[5], "-") << "ttl";
    EXPECT_EQ(f[6], "-") << "% within TTL";
    EXPECT_EQ(f[7], "-") << "logged";
    EXPECT_EQ(f[8], "1");
}

}  // namespace
}  // namespace tgw::basecamp
