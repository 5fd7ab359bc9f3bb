// tm-basecamp report --link-rate: the on-time payload of a real recording (SampleStore's SQLite file) over the
// steady window, against the link's rate.
#include "basecamp/analysis/on_time_payload.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "basecamp/analysis/report.hpp"
#include "test/unit/basecamp/recording_file.hpp"
#include "test/unit/basecamp/scratch_dir.hpp"

namespace tgw::basecamp {
namespace {

constexpr std::int64_t T0_NS = 1'800'000'000'000'000'000;
constexpr std::int64_t MS = 1'000'000;
constexpr std::int64_t S = 1'000 * MS;

class OnTimePayloadTest : public ::testing::Test {
  protected:
    void SetUp() override { recording_ = dir_.file("record.db"); }

    void declare(const std::string& topic, double ttl_s) {
        TopicRecord t;
        t.topic = topic;
        t.type_name = "T";
        t.lifespan_ns = static_cast<std::int64_t>(ttl_s * 1e9);
        t.discovered_ns = T0_NS;
        topics_.push_back(t);
    }

    /// A sample of `bytes` published `at_ns` after T0, received `transit_ns` later.
    void receive(const std::string& topic, std::int64_t at_ns, std::int64_t transit_ns, std::size_t bytes) {
        SampleRecord s;
        s.topic = topic;
        s.type_name = "T";
        s.payload.assign(bytes, 0x11);
        s.source_ns = T0_NS + at_ns;
        s.receive_ns = s.source_ns + transit_ns;
        samples_.push_back(s);
    }

    /// telemetry/A (TTL 1 s): 60 s of 100-byte samples, 10 a second, 100 ms on the way: 8,000 bit/s on time.
    void receive_a_steadily() {
        declare("telemetry/A", 1.0);
        for (std::int64_t i = 0; i < 600; ++i)
            receive("telemetry/A", i * 100 * MS, 100 * MS, 100);
    }

    std::optional<OnTimePayload> payload(double link_rate_bps, std::int64_t since_ns = 0) {
        test::write_recording(recording_, topics_, samples_);
        ReportOptions options;
        options.since_ns = since_ns;
        return read_on_time_payload(recording_, read_report(recording_, options), since_ns, link_rate_bps);
    }

    test::ScratchDir dir_{"tgw-payload"};
    std::string recording_;
    std::vector<TopicRecord> topics_;
    std::vector<SampleRecord> samples_;
};

TEST_F(OnTimePayloadTest, CountsTheBytesThatArrivedInTimeOverTheSteadyWindowAgainstTheLinkRate) {
    receive_a_steadily();
    const auto p = payload(10'000);
    ASSERT_TRUE(p);
    EXPECT_DOUBLE_EQ(p->window_start_s, 10.0);
    EXPECT_NEAR(p->window_end_s, 54.9, 1e-9);  // the last source time, 59.9 s, less 5 s
    EXPECT_EQ(p->samples, 449u);               // arrivals from 10 s to 54.9 s: published 9.9 s to 54.7 s
    EXPECT_EQ(p->bytes, 44'900u);
    EXPECT_NEAR(p->bits_per_s, 8'000.0, 1.0);
    EXPECT_NEAR(p->percent_of_link(), 80.0, 0.01);
}

TEST_F(OnTimePayloadTest, LeavesOutLateSamplesTheGatewaysOwnTopicsAndArrivalsOutsideTheWindow) {
    declare("telemetry/A", 1.0);
    declare("telemetry/D", 20.0);
    declare("tgw/status", 1.0);
    for (std::int64_t i = 0; i < 600; ++i) {
        receive("telemetry/A", i * 100 * MS, (i % 2 == 0 ? 100 : 1'500) * MS, 100);  // every other one late
        receive("tgw/status", i * 100 * MS, 10 * MS, 500);
    }
    // D is drained at the end: on time, but it arrives after the window.
    for (std::int64_t i = 0; i < 60; ++i)
        receive("telemetry/D", i * S, 19 * S, 1'000);
    const auto p = payload(10'000);
    ASSERT_TRUE(p);
    // A's on-time half that arrived from 10 to 54.9 s (224), and the D published from 0 to 35 s (36).
    EXPECT_EQ(p->samples, 224u + 36u);
    EXPECT_NEAR(p->bits_per_s, (224 * 800 + 36 * 8'000) / 44.9, 1.0);
}

TEST_F(OnTimePayloadTest, SinceMovesTheWindowWithTheFirstSourceTime) {
    receive_a_steadily();
    const auto p = payload(10'000, T0_NS + 20 * S);
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->window_end_s, 34.9, 1e-9);
    EXPECT_NEAR(p->bits_per_s, 8'000.0, 1.0);
}

TEST_F(OnTimePayloadTest, ARecordingShorterThanTheSteadyWindowGivesNoFigureAndSaysWhy) {
    declare("telemetry/A", 1.0);
    for (std::int64_t i = 0; i < 100; ++i)
        receive("telemetry/A", i * 100 * MS, 100 * MS, 100);
    const auto p = payload(10'000);
    EXPECT_FALSE(p);
    std::ostringstream out;
    print_on_time_payload(out, p, 10'000);
    EXPECT_NE(out.str().find("span less than 15 s"), std::string::npos) << out.str();
}

TEST_F(OnTimePayloadTest, PrintsTheFigureWithItsWindowAndRate) {
    receive_a_steadily();
    std::ostringstream out;
    print_on_time_payload(out, payload(10'000), 10'000);
    EXPECT_EQ(out.str(),
              "on-time payload: 8000 bit/s, 80.0 % of 10000 bit/s (449 samples, 44900 serialized bytes, that arrived "
              "within their TTL from 10 to 54.9 s after the first source time)\n");
}

}  // namespace
}  // namespace tgw::basecamp
