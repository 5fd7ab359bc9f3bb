// tm-basecamp report --robot-log: a base-camp recording and a gateway on-robot log, both real SQLite files written
// by the classes that write them in the field (SampleStore, RobotLog), matched sample by sample.
#include "basecamp/analysis/drop_accounting.hpp"

#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "basecamp/analysis/report.hpp"
#include "basecamp/recording/sample_store.hpp"
#include "gateway/log/robot_log.hpp"
#include "test/fakes/config_error_of.hpp"
#include "test/unit/basecamp/recording_file.hpp"
#include "test/unit/basecamp/scratch_dir.hpp"

namespace tgw::basecamp {
namespace {

constexpr const char* PAPER_TYPE = "tgw::idl::PaperMessage";
constexpr std::int64_t T0_NS = 1'800'000'000'000'000'000;  // a wall-clock instant in 2027
constexpr std::int64_t MS = 1'000'000;
constexpr std::int64_t PERIOD_NS = 200 * MS;  // 5 Hz

void put_u32_le(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i)
        out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

/// A serialized PaperMessage (CDR little endian): encapsulation, generated_ns, sequence_number, data.
std::vector<std::uint8_t> paper_payload(std::uint32_t sequence, std::int64_t generated_ns, std::size_t data_bytes) {
    std::vector<std::uint8_t> out = {0x00, 0x01, 0x00, 0x00};
    put_u32_le(out, static_cast<std::uint32_t>(static_cast<std::uint64_t>(generated_ns)));
    put_u32_le(out, static_cast<std::uint32_t>(static_cast<std::uint64_t>(generated_ns) >> 32));
    put_u32_le(out, sequence);
    put_u32_le(out, static_cast<std::uint32_t>(data_bytes));
    out.insert(out.end(), data_bytes, 0xAB);
    return out;
}

std::int64_t source_of(std::uint32_t sequence) {
    return T0_NS + static_cast<std::int64_t>(sequence) * PERIOD_NS;
}

/// Builds the two files of one run: the base camp's recording and the gateway's on-robot log.
class DropAccountingTest : public ::testing::Test {
  protected:
    void SetUp() override {
        recording_ = dir_.file("record.db");
        robot_log_ = dir_.file("robot-log.db");
    }

    void declare(const std::string& topic, double ttl_s, const std::string& type = PAPER_TYPE) {
        TopicRecord t;
        t.topic = topic;
        t.type_name = type;
        t.lifespan_ns = static_cast<std::int64_t>(ttl_s * 1e9);
        t.discovered_ns = T0_NS;
        topics_.push_back(t);
    }

    /// A PaperMessage of `topic` received `transit_ms` after it was published.
    void receive(const std::string& topic, std::uint32_t sequence, double transit_ms) {
        SampleRecord s;
        s.topic = topic;
        s.type_name = PAPER_TYPE;
        s.source_ns = source_of(sequence);
        s.payload = paper_payload(sequence, s.source_ns, 41);
        s.receive_ns = s.source_ns + static_cast<std::int64_t>(transit_ms * MS);
        samples_.push_back(s);
    }

    void receive_raw(SampleRecord s) { samples_.push_back(std::move(s)); }

    /// A PaperMessage of `topic` that the gateway logged with `reason`.
    void log_drop(const std::string& topic, std::uint32_t sequence, core::DropReason reason,
                  const std::string& type = PAPER_TYPE, std::int64_t source_ns = 0,
                  std::vector<std::uint8_t> payload = {}) {
        Drop d;
        d.topic = topic;
        d.type = type;
        d.sample.source_time = base::wall_from_ns(source_ns != 0 ? source_ns : source_of(sequence));
        d.sample.payload = payload.empty() ? paper_payload(sequence, source_of(sequence), 41) : std::move(payload);
        d.reason = reason;
        drops_.push_back(std::move(d));
    }

    void write_files() {
        test::write_recording(recording_, topics_, samples_);
        log::RobotLog robot_log(robot_log_);
        for (const Drop& d : drops_) {
            log::LogRecord r;
            r.topic = d.topic;
            r.type_name = d.type;
            r.sample = &d.sample;
            r.reason = d.reason;
            r.arrival = d.sample.source_time + std::chrono::milliseconds(1);
            r.deadline = d.sample.source_time + std::chrono::seconds(1);
            r.logged_at = r.deadline;
            robot_log.append(r);
        }
        robot_log.flush();
    }

    std::map<std::string, TopicReport> report(ReportOptions options) {
        write_files();
        std::map<std::string, TopicReport> by_topic;
        for (TopicReport& r : read_report(recording_, options))
            by_topic[r.topic] = r;
        return by_topic;
    }

    ReportOptions with_log() const {
        ReportOptions options;
        options.robot_log = robot_log_;
        return options;
    }

    struct Drop {
        std::string topic;
        std::string type;
        core::Sample sample;
        core::DropReason reason = core::DropReason::expired;
    };

    test::ScratchDir dir_{"tgw-accounting"};
    std::string recording_;
    std::string robot_log_;
    std::vector<TopicRecord> topics_;
    std::vector<SampleRecord> samples_;
    std::vector<Drop> drops_;
};

std::uint64_t dropped(const DropAccounting& a, core::DropReason reason) {
    return a.dropped[static_cast<std::size_t>(reason)];
}

TEST_F(DropAccountingTest, AccountsForEveryPublishedSampleByItsReason) {
    declare("telemetry/A", 1.0);
    for (std::uint32_t seq = 0; seq < 5; ++seq)
        receive("telemetry/A", seq, 80.0);
    receive("telemetry/A", 5, 1500.0);  // late
    log_drop("telemetry/A", 6, core::DropReason::expired);
    log_drop("telemetry/A", 7, core::DropReason::doomed);
    log_drop("telemetry/A", 8, core::DropReason::evicted);
    log_drop("telemetry/A", 9, core::DropReason::oversize);
    log_drop("telemetry/A", 10, core::DropReason::shutdown);
    // 11 and 12: published, never received, not in the log: lost on the link.
    ReportOptions options = with_log();
    options.offered["telemetry/A"] = 13;

    const auto reports = report(options);

    ASSERT_TRUE(reports.at("telemetry/A").accounting);
    const DropAccounting& sut = *reports.at("telemetry/A").accounting;
    EXPECT_TRUE(sut.by_sequence);
    EXPECT_EQ(sut.offered, 13u);
    EXPECT_EQ(sut.received, 6u);
    EXPECT_EQ(sut.on_time, 5u);
    EXPECT_EQ(dropped(sut, core::DropReason::expired), 1u);
    EXPECT_EQ(dropped(sut, core::DropReason::doomed), 1u);
    EXPECT_EQ(dropped(sut, core::DropReason::evicted), 1u);
    EXPECT_EQ(dropped(sut, core::DropReason::oversize), 1u);
    EXPECT_EQ(dropped(sut, core::DropReason::shutdown), 1u);
    EXPECT_EQ(sut.lost_on_link, 2u);
    EXPECT_TRUE(sut.lost_inferred);
    EXPECT_EQ(sut.unaccounted, 0);
}

TEST_F(DropAccountingTest, ReportsATopicOfWhichNothingArrived) {
    declare("telemetry/A", 1.0);
    receive("telemetry/A", 0, 50.0);
    declare("telemetry/D", 20.0);
    log_drop("telemetry/D", 0, core::DropReason::expired);
    log_drop("telemetry/D", 1, core::DropReason::shutdown);
    ReportOptions options = with_log();
    options.offered["telemetry/A"] = 1;
    options.offered["telemetry/D"] = 3;

    const auto reports = report(options);

    const DropAccounting& sut = *reports.at("telemetry/D").accounting;
    EXPECT_EQ(sut.received, 0u);
    EXPECT_EQ(dropped(sut, core::DropReason::expired), 1u);
    EXPECT_EQ(dropped(sut, core::DropReason::shutdown), 1u);
    EXPECT_EQ(sut.lost_on_link, 1u);
    EXPECT_EQ(sut.unaccounted, 0);
}

TEST_F(DropAccountingTest, ForwardedCountMakesLinkLossExactAndLeavesTheRestUnaccounted) {
    declare("telemetry/B", 2.0);
    for (std::uint32_t seq = 0; seq < 6; ++seq)
        receive("telemetry/B", seq, 100.0);
    log_drop("telemetry/B", 6, core::DropReason::doomed);
    ReportOptions options = with_log();
    options.offered["telemetry/B"] = 10;
    options.forwarded["telemetry/B"] = 7;  // one forwarded sample never arrived; two never reached the gateway

    const auto reports = report(options);

    const DropAccounting& sut = *reports.at("telemetry/B").accounting;
    EXPECT_EQ(sut.lost_on_link, 1u);
    EXPECT_FALSE(sut.lost_inferred);
    EXPECT_EQ(sut.unaccounted, 2);
}

TEST_F(DropAccountingTest, CountsOfferedFromTheLogsSequenceNumbersToo) {
    declare("telemetry/C", 5.0);
    receive("telemetry/C", 0, 300.0);
    receive("telemetry/C", 2, 300.0);
    log_drop("telemetry/C", 4, core::DropReason::expired);  // after the last one received

    const auto reports = report(with_log());

    const TopicReport& r = reports.at("telemetry/C");
    EXPECT_EQ(r.offered, 5u);
    EXPECT_EQ(r.offered_from, "sequence");
    EXPECT_EQ(r.accounting->lost_on_link, 2u);  // 1 and 3
}

TEST_F(DropAccountingTest, MatchesBySourceTimestampWhenThePayloadHasNoSequence) {
    const std::string type = "std_msgs::msg::dds_::String_";
    declare("rt/chatter", 1.0, type);
    const std::vector<std::uint8_t> hello = {0x00, 0x01, 0x00, 0x00, 0x06, 0x00, 0x00,
                                             0x00, 'h',  'e',  'l',  'l',  'o',  0};
    for (int i = 0; i < 3; ++i) {
        SampleRecord s;
        s.topic = "rt/chatter";
        s.type_name = type;
        s.payload = hello;
        s.source_ns = T0_NS + i * PERIOD_NS;
        s.receive_ns = s.source_ns + 20 * MS;
        receive_raw(s);
    }
    // The log's source time of sample 2 is a nanosecond off (RTPS time conversion): still the same sample.
    log_drop("rt/chatter", 0, core::DropReason::expired, type, T0_NS + 2 * PERIOD_NS + 1, hello);
    log_drop("rt/chatter", 0, core::DropReason::expired, type, T0_NS + 3 * PERIOD_NS, hello);
    ReportOptions options = with_log();
    options.offered["rt/chatter"] = 5;

    const auto reports = report(options);

    const DropAccounting& sut = *reports.at("rt/chatter").accounting;
    EXPECT_FALSE(sut.by_sequence);
    EXPECT_EQ(sut.received, 3u);
    EXPECT_EQ(sut.logged_and_received, 1u);
    EXPECT_EQ(dropped(sut, core::DropReason::expired), 1u);
    EXPECT_EQ(sut.lost_on_link, 1u);
}

TEST_F(DropAccountingTest, SinceIgnoresEarlierSamplesInBothFiles) {
    declare("telemetry/A", 1.0);
    // A warm-up publisher used sequences 0..2 a minute earlier; they must not be taken for the measured ones.
    for (std::uint32_t seq = 0; seq < 3; ++seq) {
        SampleRecord s;
        s.topic = "telemetry/A";
        s.type_name = PAPER_TYPE;
        s.source_ns = T0_NS - 60'000 * MS + seq * PERIOD_NS;
        s.payload = paper_payload(seq, s.source_ns, 41);
        s.receive_ns = s.source_ns + 50 * MS;
        receive_raw(s);
    }
    log_drop("telemetry/A", 1, core::DropReason::doomed, PAPER_TYPE, T0_NS - 60'000 * MS + PERIOD_NS);
    receive("telemetry/A", 0, 50.0);
    log_drop("telemetry/A", 1, core::DropReason::expired);
    ReportOptions options = with_log();
    options.offered["telemetry/A"] = 3;
    options.since_ns = T0_NS;

    const auto reports = report(options);

    const TopicReport& r = reports.at("telemetry/A");
    EXPECT_EQ(r.received, 1u);
    const DropAccounting& sut = *r.accounting;
    EXPECT_EQ(sut.received, 1u);
    EXPECT_EQ(sut.logged_and_received, 0u);
    EXPECT_EQ(dropped(sut, core::DropReason::expired), 1u);
    EXPECT_EQ(dropped(sut, core::DropReason::doomed), 0u);
    EXPECT_EQ(sut.lost_on_link, 1u);
}

TEST_F(DropAccountingTest, DuplicateReceptionsCountOnce) {
    declare("telemetry/A", 1.0);
    receive("telemetry/A", 0, 50.0);
    receive("telemetry/A", 0, 60.0);
    ReportOptions options = with_log();
    options.offered["telemetry/A"] = 1;

    const auto reports = report(options);

    const DropAccounting& sut = *reports.at("telemetry/A").accounting;
    EXPECT_EQ(sut.received, 1u);
    EXPECT_EQ(sut.duplicates_received, 1u);
    EXPECT_EQ(sut.lost_on_link, 0u);
}

TEST_F(DropAccountingTest, PrintsTheAccountingTable) {
    declare("telemetry/A", 1.0);
    receive("telemetry/A", 0, 50.0);
    log_drop("telemetry/A", 1, core::DropReason::doomed);
    ReportOptions options = with_log();
    options.offered["telemetry/A"] = 3;

    write_files();
    std::ostringstream out;
    print_report(out, read_report(recording_, options));

    const std::string text = out.str();
    EXPECT_NE(text.find("lost_link"), std::string::npos) << text;
    EXPECT_NE(text.find("unaccounted"), std::string::npos) << text;
    // topic, offered 3, received 1, on time 1, late 0, expired 0, doomed 1, evicted/oversize/shutdown/write_failed/
    // no_reader/rate_capped/superseded 0, lost 1*
    std::istringstream lines(text);
    std::string line;
    bool found = false;
    while (std::getline(lines, line)) {
        std::istringstream fields(line);
        std::vector<std::string> f;
        for (std::string x; fields >> x;)
            f.push_back(x);
        if (f.size() == 17 && f[0] == "telemetry/A") {
            found = true;
            EXPECT_EQ(f[1], "3");
            EXPECT_EQ(f[2], "1");
            EXPECT_EQ(f[6], "1");    // doomed
            EXPECT_EQ(f[10], "0");   // write_failed
            EXPECT_EQ(f[11], "0");   // no_reader
            EXPECT_EQ(f[13], "0");   // superseded
            EXPECT_EQ(f[14], "1*");  // lost on the link, inferred
            EXPECT_EQ(f[15], "0");   // unaccounted
            EXPECT_EQ(f[16], "sequence");
        }
    }
    EXPECT_TRUE(found) << text;
}

TEST_F(DropAccountingTest, WithoutARobotLogThereIsNoAccounting) {
    declare("telemetry/A", 1.0);
    receive("telemetry/A", 0, 50.0);

    const auto reports = report(ReportOptions{});

    EXPECT_FALSE(reports.at("telemetry/A").accounting);
}

TEST_F(DropAccountingTest, RejectsAFileThatIsNotAnOnRobotLog) {
    write_files();

    const std::string error = test::config_error_of([&] { read_robot_log(recording_, "--robot-log", 0); });

    EXPECT_NE(error.find("--robot-log"), std::string::npos) << error;
    EXPECT_NE(error.find("record.db"), std::string::npos) << error;
    EXPECT_NE(error.find("not an on-robot log"), std::string::npos) << error;
}

TEST(AccountTopic, UnknownReasonsCountAsUnaccounted) {
    const std::vector<ReceivedSample> received = {{0, T0_NS, 10.0}};
    const std::vector<LoggedSample> logged = {{"t", 1, source_of(1), "vanished"}};

    const DropAccounting sut = account_topic(received, logged, 1.0, 2, std::nullopt);

    EXPECT_EQ(sut.dropped_other, 1u);
    EXPECT_EQ(sut.lost_on_link, 0u);
    EXPECT_EQ(sut.unaccounted, 1);
}

TEST(AccountTopic, WithoutOfferedOrForwardedLinkLossIsUnknown) {
    const DropAccounting sut = account_topic({{0, T0_NS, 10.0}}, {}, std::nullopt, std::nullopt, std::nullopt);

    EXPECT_FALSE(sut.lost_on_link);
    EXPECT_FALSE(sut.unaccounted);
    EXPECT_FALSE(sut.on_time);
    EXPECT_EQ(sut.received, 1u);
}

}  // namespace
}  // namespace tgw::basecamp
