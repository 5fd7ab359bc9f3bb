// A recording that holds backfilled samples (rows of the on-robot log that missed their TTL and came later), read
// back: `report` keeps them out of the live figures and counts them apart; RecordingReader (export, linkmap) hands
// them at their source time with their origin, so an MCAP file plays the mission in the order the robot lived it.
#include <gtest/gtest.h>

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "basecamp/analysis/report.hpp"
#include "basecamp/recording/recording_reader.hpp"
#include "basecamp/sample/sample_consumer.hpp"
#include "test/unit/basecamp/recording_file.hpp"
#include "test/unit/basecamp/scratch_dir.hpp"

namespace tgw::basecamp {
namespace {

constexpr std::int64_t T0_NS = 1'800'000'000'000'000'000;
constexpr std::int64_t MS = 1'000'000;
constexpr std::int64_t S = 1'000 * MS;
const std::string LOG_ID = "0123456789abcdef0123456789abcdef";

SampleRecord live(const std::string& topic, std::int64_t source_ms, std::int64_t transit_ms) {
    SampleRecord s;
    s.topic = topic;
    s.type_name = "tgw::idl::Reading";
    s.payload = {0x00, 0x01, 0x00, 0x00, static_cast<std::uint8_t>(source_ms / 100)};
    s.source_ns = T0_NS + source_ms * MS;
    s.receive_ns = s.source_ns + transit_ms * MS;
    s.lifespan_ns = 1 * S;
    return s;
}

/// Row `row_id` of the robot's log: published `source_ms` after T0, at the camp a minute after that.
SampleRecord backfilled(const std::string& topic, std::int64_t row_id, std::int64_t source_ms) {
    SampleRecord s = live(topic, source_ms, 60'000);
    s.backfill = BackfillOrigin{LOG_ID, row_id, "expired"};
    return s;
}

class Collected final : public SampleConsumer {
  public:
    void add_topic(TopicRecord) override {}
    void add(SampleRecord sample) override { samples.push_back(std::move(sample)); }
    std::vector<SampleRecord> samples;
};

class BackfilledReadbackTest : public ::testing::Test {
  protected:
    void SetUp() override {
        // telemetry/A: three live, on time, late and on time; one backfilled between them. telemetry/B: only one,
        // backfilled.
        test::write_recording(
            recording_, {},
            {live("telemetry/A", 0, 100), live("telemetry/A", 200, 1'500), backfilled("telemetry/A", 7, 400),
             live("telemetry/A", 600, 200), backfilled("telemetry/B", 9, 300)});
    }

    test::ScratchDir dir_{"tgw-backfilled-readback"};
    const std::string recording_ = dir_.file("recording.db");
};

TEST_F(BackfilledReadbackTest, ReportCountsOnlyLiveSamplesAndBackfilledApart) {
    const std::vector<TopicReport> reports = read_report(recording_, ReportOptions{});
    ASSERT_EQ(reports.size(), 2u);
    EXPECT_EQ(reports[0].topic, "telemetry/A");
    EXPECT_EQ(reports[0].received, 3u);
    EXPECT_EQ(reports[0].on_time, 2u);
    EXPECT_DOUBLE_EQ(reports[0].max_ms, 1'500.0);  // the backfilled minute is no transit time
    EXPECT_EQ(reports[0].backfilled, 1u);
    EXPECT_EQ(reports[1].topic, "telemetry/B");
    EXPECT_EQ(reports[1].received, 0u);
    EXPECT_EQ(reports[1].backfilled, 1u);

    std::ostringstream printed;
    print_report(printed, reports);
    EXPECT_NE(printed.str().find("backfilled (missed their TTL, reached the recording later from the on-robot log; "
                                 "in no figure above): telemetry/A 1, telemetry/B 1"),
              std::string::npos)
        << printed.str();
}

TEST_F(BackfilledReadbackTest, ReaderHandsBackfilledSamplesAtTheirSourceTimeWithTheirOrigin) {
    RecordingReader reader(recording_, "FILE");
    Collected collected;
    EXPECT_EQ(reader.read(collected), 5u);

    // In the order of the mission: live ones by receive time, backfilled ones by source time.
    std::vector<std::int64_t> order_ms;
    for (const SampleRecord& s : collected.samples)
        order_ms.push_back((s.source_ns - T0_NS) / MS);
    EXPECT_EQ(order_ms, (std::vector<std::int64_t>{0, 300, 400, 600, 200}));

    const SampleRecord& b = collected.samples[1];
    ASSERT_TRUE(b.backfill.has_value());
    EXPECT_EQ(b.backfill->log_id, LOG_ID);
    EXPECT_EQ(b.backfill->row_id, 9);
    EXPECT_EQ(b.backfill->reason, "expired");
    EXPECT_EQ(b.receive_ns - b.source_ns, 60 * S);  // when it reached the camp, kept
    EXPECT_FALSE(collected.samples[0].backfill.has_value());
}

}  // namespace
}  // namespace tgw::basecamp
