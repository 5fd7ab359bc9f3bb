// tm-basecamp merge: an on-robot log and a base-camp recording, both real SQLite files written by the classes that
// write them in the field (RobotLog, SampleStore), merged into the mission archive and read back with SQL.
#include "basecamp/analysis/mission_archive.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "basecamp/recording/sample_store.hpp"
#include "gateway/log/robot_log.hpp"
#include "test/fakes/config_error_of.hpp"
#include "test/unit/basecamp/recording_file.hpp"
#include "test/unit/basecamp/scratch_dir.hpp"

namespace tgw::basecamp {
namespace {

namespace fs = std::filesystem;

constexpr const char* TYPE = "tgw::idl::PaperMessage";
constexpr std::int64_t T0_NS = 1'800'000'000'000'000'000;  // a wall-clock instant in 2027
constexpr std::int64_t MS = 1'000'000;

std::vector<std::uint8_t> payload(std::size_t bytes, std::uint8_t fill = 0xAB) {
    std::vector<std::uint8_t> out = {0x00, 0x01, 0x00, 0x00};  // CDR little endian, as received
    out.insert(out.end(), bytes, fill);
    return out;
}

core::InstanceKey key(std::uint8_t id) {
    core::InstanceKey k;
    k.bytes.fill(0);
    k.bytes[0] = id;
    k.valid = true;
    return k;
}

/// Runs one SQL query on a file and gives each row as text, columns as SQLite's quote() writes them.
std::vector<std::string> query(const std::string& path, const std::string& sql) {
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK) << path;
    sqlite3_stmt* stmt = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
    std::vector<std::string> rows;
    while (stmt != nullptr && sqlite3_step(stmt) == SQLITE_ROW) {
        std::string row;
        for (int i = 0; i < sqlite3_column_count(stmt); ++i) {
            const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt, i));
            row += (i > 0 ? "|" : "") + std::string(text != nullptr ? text : "NULL");
        }
        rows.push_back(row);
    }
    sqlite3_finalize(stmt);
    sqlite3_close(db);
    return rows;
}

/// Every value of the archive's two tables, in id (and key) order: what "the same archive" means.
std::vector<std::string> dump(const std::string& archive) {
    std::vector<std::string> rows;
    for (const char* table : {"mission_samples", "meta"}) {
        std::string columns;
        for (const std::string& name :
             query(archive, std::string("SELECT name FROM pragma_table_info('") + table + "') ORDER BY cid"))
            columns += (columns.empty() ? "quote(" : ", quote(") + name + ")";
        for (std::string& row : query(archive, "SELECT " + columns + " FROM " + table + " ORDER BY 1"))
            rows.push_back(std::string(table) + ": " + row);
    }
    return rows;
}

class MissionArchiveTest : public ::testing::Test {
  protected:
    void SetUp() override {
        robot_log_ = dir_.file("robot-log.db");
        recording_ = dir_.file("basecamp.db");
        archive_ = dir_.file("mission.db");
    }

    void declare(const std::string& topic, std::optional<std::int64_t> lifespan_ns) {
        TopicRecord t;
        t.topic = topic;
        t.type_name = TYPE;
        t.lifespan_ns = lifespan_ns;
        t.discovered_ns = T0_NS;
        topics_.push_back(t);
    }

    /// A sample the gateway wrote to the WAN.
    void forward(const std::string& topic, std::int64_t source_ns, std::size_t bytes,
                 std::optional<core::InstanceKey> instance = std::nullopt) {
        robot_rows_.push_back({topic, sample(source_ns, bytes, instance), std::nullopt});
    }

    /// A sample the gateway logged with `reason` instead.
    void drop(const std::string& topic, std::int64_t source_ns, std::size_t bytes, core::DropReason reason) {
        robot_rows_.push_back({topic, sample(source_ns, bytes, std::nullopt), reason});
    }

    /// A sample the base camp recorded `transit_ms` after its source time.
    void record(const std::string& topic, std::int64_t source_ns, std::size_t bytes, double transit_ms,
                std::optional<core::InstanceKey> instance = std::nullopt) {
        SampleRecord s;
        s.topic = topic;
        s.type_name = TYPE;
        s.payload = payload(bytes);
        s.source_ns = source_ns;
        s.receive_ns = source_ns + static_cast<std::int64_t>(transit_ms * MS);
        for (const TopicRecord& t : topics_)
            if (t.topic == topic)
                s.lifespan_ns = t.lifespan_ns;
        if (instance)
            s.instance.assign(instance->bytes.begin(), instance->bytes.end());
        samples_.push_back(s);
    }

    void write_files() {
        test::write_recording(recording_, topics_, samples_);
        log::RobotLog log(robot_log_);
        for (const RobotRow& r : robot_rows_) {
            const base::WallTime arrival = r.sample.source_time + std::chrono::milliseconds(1);
            const base::WallTime deadline = r.sample.source_time + std::chrono::seconds(1);
            if (r.reason) {
                log.append({r.topic, TYPE, &r.sample, *r.reason, arrival, deadline, deadline});
            } else {
                log.append_forwarded({r.topic, TYPE, &r.sample, arrival, deadline, arrival, std::nullopt});
            }
        }
        log.flush();
        robot_rows_.clear();
        samples_.clear();
        topics_.clear();
    }

    /// Makes the robot log one that a gateway before forwarded_samples wrote.
    void make_the_log_older() const {
        sqlite3* db = nullptr;
        ASSERT_EQ(sqlite3_open(robot_log_.c_str(), &db), SQLITE_OK);
        EXPECT_EQ(sqlite3_exec(db, "DROP TABLE forwarded_samples", nullptr, nullptr, nullptr), SQLITE_OK);
        sqlite3_close(db);
    }

    MergeCounts merge(const std::string& out) {
        const std::optional<MergeCounts> counts = merge_mission(robot_log_, recording_, out);
        EXPECT_TRUE(counts.has_value());
        return counts.value_or(MergeCounts{});
    }

    MergeCounts write_and_merge() {
        write_files();
        return merge(archive_);
    }

    static const TopicFates& fates_of(const MergeCounts& counts, const std::string& topic) {
        for (const TopicFates& t : counts.topics)
            if (t.topic == topic)
                return t;
        static const TopicFates none;
        ADD_FAILURE() << "no topic " << topic << " in the counts";
        return none;
    }

    std::vector<std::string> archive_rows(const std::string& columns, const std::string& where = "1") const {
        return query(archive_, "SELECT " + columns + " FROM mission_samples WHERE " + where + " ORDER BY id");
    }

    struct RobotRow {
        std::string topic;
        core::Sample sample;
        std::optional<core::DropReason> reason;  ///< empty: forwarded
    };

    static core::Sample sample(std::int64_t source_ns, std::size_t bytes, std::optional<core::InstanceKey> instance) {
        core::Sample s;
        s.source_time = base::wall_from_ns(source_ns);
        s.payload = payload(bytes);
        if (instance)
            s.key = *instance;
        return s;
    }

    test::ScratchDir dir_{"tgw-archive"};
    std::string robot_log_;
    std::string recording_;
    std::string archive_;
    std::vector<TopicRecord> topics_;
    std::vector<SampleRecord> samples_;
    std::vector<RobotRow> robot_rows_;
};

TEST_F(MissionArchiveTest, HoldsEverySampleOnceWithWhereItEndedUp) {
    declare("telemetry/A", 1000 * MS);
    forward("telemetry/A", T0_NS, 41);
    forward("telemetry/A", T0_NS + 200 * MS, 41);
    forward("telemetry/A", T0_NS + 400 * MS, 41);
    drop("telemetry/A", T0_NS + 600 * MS, 41, core::DropReason::expired);
    drop("telemetry/A", T0_NS + 800 * MS, 41, core::DropReason::doomed);
    record("telemetry/A", T0_NS, 41, 50.0);
    record("telemetry/A", T0_NS + 400 * MS, 41, 70.0);

    const MergeCounts counts = write_and_merge();

    EXPECT_EQ(archive_rows("source_ns - " + std::to_string(T0_NS) + ", fate, reason, payload IS NULL"),
              (std::vector<std::string>{"0|received|NULL|0", "200000000|lost|NULL|1", "400000000|received|NULL|0",
                                        "600000000|dropped|expired|0", "800000000|dropped|doomed|0"}));
    const TopicFates& a = fates_of(counts, "telemetry/A");
    EXPECT_EQ(a.produced(), 5u);
    EXPECT_EQ(a.received, 2u);
    EXPECT_EQ(a.lost, 1u);
    EXPECT_EQ(a.dropped_total(), 2u);
    EXPECT_EQ(a.dropped[static_cast<std::size_t>(core::DropReason::expired)], 1u);
    EXPECT_EQ(a.dropped[static_cast<std::size_t>(core::DropReason::doomed)], 1u);
    EXPECT_EQ(a.received_unmatched, 0u);
    EXPECT_EQ(counts.total.produced(), 5u);
}

TEST_F(MissionArchiveTest, ABackfilledSampleStaysDroppedWithItsReasonAndGainsTheArchivesReceiveTime) {
    declare("telemetry/C", 5000 * MS);
    forward("telemetry/C", T0_NS, 400);
    drop("telemetry/C", T0_NS + 200 * MS, 400, core::DropReason::expired);
    drop("telemetry/C", T0_NS + 400 * MS, 400, core::DropReason::doomed);
    record("telemetry/C", T0_NS, 400, 50.0);
    write_files();
    // The camp's archive gets the first dropped row later by backfill, and a row of another robot's log.
    const std::string log_id = query(robot_log_, "SELECT value FROM meta WHERE key = 'log_id'").at(0);
    const std::vector<std::string> rows = query(robot_log_, "SELECT id FROM dropped_samples ORDER BY id");
    ASSERT_EQ(rows.size(), 2u);
    const auto backfilled = [&](const std::string& log, const std::string& row) {
        SampleRecord s;
        s.topic = "telemetry/C";
        s.type_name = TYPE;
        s.payload = payload(400);
        s.source_ns = T0_NS + 200 * MS;
        s.receive_ns = T0_NS + 60'000 * MS;
        s.backfill = BackfillOrigin{log, std::stoll(row), "expired"};
        return s;
    };
    test::write_recording(recording_, {},
                          {backfilled(log_id, rows[0]), backfilled("00112233445566778899aabbccddeeff", rows[1])});

    const MergeCounts counts = merge(archive_);

    EXPECT_EQ(archive_rows("source_ns - " + std::to_string(T0_NS) + ", fate, reason, backfilled, receive_ns - " +
                           std::to_string(T0_NS)),
              (std::vector<std::string>{"0|received|NULL|0|50000000", "200000000|dropped|expired|1|60000000000",
                                        "400000000|dropped|doomed|0|NULL"}))
        << "the other log's row is not this robot's";
    const TopicFates& c = fates_of(counts, "telemetry/C");
    EXPECT_EQ(c.produced(), 3u) << "each sample once";
    EXPECT_EQ(c.received, 1u);
    EXPECT_EQ(c.dropped_total(), 2u);
    EXPECT_EQ(c.backfilled, 1u);
    EXPECT_EQ(c.received_unmatched, 0u) << "a backfilled sample pairs with its dropped row, not as received";
}

TEST_F(MissionArchiveTest, ABackfilledSampleWhoseRowTheLogFreedAtItsCapStaysWithTheReasonTheCampStored) {
    // A log capped at 1 MiB: one expired row, which the camp backfills and acknowledges, then enough doomed rows
    // to pass the cap, which frees the acknowledged row first (RobotLog's order).
    constexpr std::size_t BIG = 10'000;
    const core::Sample expired = sample(T0_NS, BIG, std::nullopt);
    std::string log_id;
    std::int64_t expired_row = 0;
    {
        log::RobotLog log(robot_log_, 1u << 20);
        const base::WallTime at = expired.source_time + std::chrono::seconds(1);
        log.append({"telemetry/D", TYPE, &expired, core::DropReason::expired, at, at, at});
        log.flush();
        expired_row = log.unacknowledged(0, 1).at(0).row_id;
        log_id = log.log_id();
        log.mark_acknowledged(expired_row, expired_row, at);
        log.flush();
        for (int i = 1; i <= 110; ++i) {
            const core::Sample doomed = sample(T0_NS + i * MS, BIG, std::nullopt);
            log.append({"telemetry/D", TYPE, &doomed, core::DropReason::doomed, at, at, at});
            log.flush();
        }
    }
    ASSERT_EQ(query(robot_log_, "SELECT COUNT(*) FROM dropped_samples WHERE id = " + std::to_string(expired_row)),
              std::vector<std::string>{"0"})
        << "the cap must have freed the acknowledged row";
    SampleRecord s;
    s.topic = "telemetry/D";
    s.type_name = TYPE;
    s.payload = payload(BIG);
    s.source_ns = T0_NS;
    s.receive_ns = T0_NS + 90'000 * MS;
    s.backfill = BackfillOrigin{log_id, expired_row, "expired"};
    test::write_recording(recording_, {}, {s});

    const MergeCounts counts = merge(archive_);

    EXPECT_EQ(archive_rows("fate, reason, backfilled, receive_ns - source_ns, robot_row IS NULL", "reason = 'expired'"),
              std::vector<std::string>{"dropped|expired|1|90000000000|1"});
    const TopicFates& d = fates_of(counts, "telemetry/D");
    const auto logged = query(robot_log_, "SELECT COUNT(*) FROM dropped_samples");
    EXPECT_EQ(d.produced(), std::stoull(logged.at(0)) + 1) << "what the log keeps, and the freed row once";
    EXPECT_EQ(d.backfilled, 1u);
    EXPECT_EQ(d.dropped[static_cast<std::size_t>(core::DropReason::expired)], 1u);
    EXPECT_EQ(d.received_unmatched, 0u);
}

TEST_F(MissionArchiveTest, AReceivedSampleCarriesItsLatencyAndWhetherItCameWithinTheRecordedLifespan) {
    declare("telemetry/A", 1000 * MS);
    declare("no/lifespan", std::nullopt);
    forward("telemetry/A", T0_NS, 41);
    forward("telemetry/A", T0_NS + 200 * MS, 41);
    forward("no/lifespan", T0_NS, 41);
    record("telemetry/A", T0_NS, 41, 250.0);
    record("telemetry/A", T0_NS + 200 * MS, 41, 1500.0);
    record("no/lifespan", T0_NS, 41, 10.0);

    const MergeCounts counts = write_and_merge();

    EXPECT_EQ(archive_rows("latency_ns, ttl_ns, on_time, receive_ns - source_ns, forwarded_ns - source_ns",
                           "topic = 'telemetry/A'"),
              (std::vector<std::string>{"250000000|1000000000|1|250000000|1000000",
                                        "1500000000|1000000000|0|1500000000|1000000"}));
    EXPECT_EQ(archive_rows("ttl_ns, on_time", "topic = 'no/lifespan'"), (std::vector<std::string>{"NULL|NULL"}));
    EXPECT_EQ(fates_of(counts, "telemetry/A").on_time, std::optional<std::uint64_t>(1));
    EXPECT_EQ(fates_of(counts, "no/lifespan").on_time, std::nullopt);
}

TEST_F(MissionArchiveTest, KeepsEveryDropReasonOfTheRobotLogByName) {
    declare("telemetry/D", 20'000 * MS);
    for (std::size_t i = 0; i < core::DROP_REASON_COUNT; ++i)
        drop("telemetry/D", T0_NS + static_cast<std::int64_t>(i) * MS, 1016, static_cast<core::DropReason>(i));

    const MergeCounts counts = write_and_merge();

    EXPECT_EQ(archive_rows("reason"),
              (std::vector<std::string>{"expired", "doomed", "evicted", "oversize", "shutdown", "write_failed",
                                        "no_reader", "rate_capped", "superseded"}));
    for (std::size_t i = 0; i < core::DROP_REASON_COUNT; ++i)
        EXPECT_EQ(fates_of(counts, "telemetry/D").dropped[i], 1u) << core::DROP_REASON_NAMES[i];
    EXPECT_EQ(archive_rows("COUNT(*)", "payload_bytes = length(payload) AND logged_ns IS NOT NULL"),
              (std::vector<std::string>{"9"}));
}

TEST_F(MissionArchiveTest, MatchesIdenticalSamplesByMultiplicity) {
    declare("twice", 1000 * MS);
    declare("thrice", 1000 * MS);
    // Two identical samples forwarded (same topic, time, size), one recorded: one received, one lost.
    forward("twice", T0_NS, 41);
    forward("twice", T0_NS, 41);
    record("twice", T0_NS, 41, 10.0);
    // Two forwarded, three recorded: the third has no robot row.
    forward("thrice", T0_NS, 41);
    forward("thrice", T0_NS, 41);
    record("thrice", T0_NS, 41, 10.0);
    record("thrice", T0_NS, 41, 11.0);
    record("thrice", T0_NS, 41, 12.0);

    const MergeCounts counts = write_and_merge();

    EXPECT_EQ(fates_of(counts, "twice").received, 1u);
    EXPECT_EQ(fates_of(counts, "twice").lost, 1u);
    EXPECT_EQ(fates_of(counts, "thrice").received, 3u);
    EXPECT_EQ(fates_of(counts, "thrice").received_unmatched, 1u);
    EXPECT_EQ(fates_of(counts, "thrice").lost, 0u);
    EXPECT_EQ(archive_rows("COUNT(DISTINCT robot_row), COUNT(DISTINCT basecamp_row)", "topic = 'thrice'"),
              (std::vector<std::string>{"2|3"}));
}

TEST_F(MissionArchiveTest, TellsTheInstancesOfAKeyedTopicApart) {
    declare("keyed", 1000 * MS);
    forward("keyed", T0_NS, 16, key(1));
    forward("keyed", T0_NS, 16, key(2));
    record("keyed", T0_NS, 16, 10.0, key(2));

    write_and_merge();

    EXPECT_EQ(archive_rows("fate, hex(instance_key)"),
              (std::vector<std::string>{"lost|01000000000000000000000000000000",
                                        "received|02000000000000000000000000000000"}));
}

TEST_F(MissionArchiveTest, MatchesASourceTimeThatRtpsRoundedByANanosecond) {
    declare("telemetry/A", 1000 * MS);
    forward("telemetry/A", T0_NS + 7, 41);
    record("telemetry/A", T0_NS + 6, 41, 10.0);

    const MergeCounts counts = write_and_merge();

    EXPECT_EQ(counts.total.received, 1u);
    EXPECT_EQ(counts.total.lost, 0u);
    EXPECT_EQ(counts.total.received_unmatched, 0u);
    EXPECT_EQ(archive_rows("source_ns - " + std::to_string(T0_NS)), (std::vector<std::string>{"7"}))
        << "the robot's source time is the sample's";
}

TEST_F(MissionArchiveTest, KeepsARecordedSampleNoRobotRowMatchesAsReceivedWithoutRobotColumns) {
    declare("telemetry/A", 1000 * MS);
    forward("telemetry/A", T0_NS + 200 * MS, 41);
    record("telemetry/A", T0_NS, 41, 10.0);  // recorded before the log began
    record("telemetry/A", T0_NS + 200 * MS, 41, 10.0);

    const MergeCounts counts = write_and_merge();

    EXPECT_EQ(counts.total.received, 2u);
    EXPECT_EQ(counts.total.received_unmatched, 1u);
    EXPECT_EQ(archive_rows("fate, robot_row IS NULL, arrival_ns IS NULL, forwarded_ns IS NULL, latency_ns"),
              (std::vector<std::string>{"received|1|1|1|10000000", "received|0|0|0|10000000"}));
}

TEST_F(MissionArchiveTest, LeavesOutTheToolsOwnTopics) {
    declare("tgw/status", 1000 * MS);
    declare("telemetry/A", 1000 * MS);
    record("tgw/status", T0_NS, 600, 10.0);
    record("tgw/receiver_report", T0_NS, 60, 10.0);
    forward("telemetry/A", T0_NS, 41);
    record("telemetry/A", T0_NS, 41, 10.0);

    const MergeCounts counts = write_and_merge();

    EXPECT_EQ(archive_rows("topic"), (std::vector<std::string>{"telemetry/A"}));
    ASSERT_EQ(counts.topics.size(), 1u);
}

TEST_F(MissionArchiveTest, MergingAgainGivesTheSameArchive) {
    declare("telemetry/A", 1000 * MS);
    declare("keyed", 2000 * MS);
    for (std::int64_t i = 0; i < 50; ++i) {
        const std::int64_t t = T0_NS + i * 200 * MS;
        if (i % 5 == 0) {
            drop("telemetry/A", t, 41, core::DropReason::expired);
            continue;
        }
        forward("telemetry/A", t, 41);
        forward("keyed", t, 16, key(static_cast<std::uint8_t>(i % 3)));
        if (i % 7 != 0)
            record("telemetry/A", t, 41, 30.0 + static_cast<double>(i));
        record("keyed", t, 16, 20.0, key(static_cast<std::uint8_t>(i % 3)));
    }
    record("telemetry/A", T0_NS + 60'000 * MS, 41, 10.0);  // after the log ended
    const MergeCounts first = write_and_merge();
    const std::vector<std::string> before = dump(archive_);
    const std::string elsewhere = dir_.file("again.db");

    const MergeCounts second = merge(elsewhere);
    const MergeCounts replaced = merge(archive_);

    EXPECT_EQ(first.total.produced(), 50u + 40u + 1u);
    ASSERT_EQ(before.size(), 50u + 40u + 1u + 3u);
    EXPECT_EQ(dump(elsewhere), before);
    EXPECT_EQ(dump(archive_), before);
    EXPECT_EQ(second.total.produced(), first.total.produced());
    EXPECT_EQ(replaced.total.lost, first.total.lost);
    for (const auto& entry : fs::directory_iterator(dir_.path()))
        EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos) << entry.path();
}

TEST_F(MissionArchiveTest, NamesAnInputThatIsNotWhatItShouldBe) {
    write_files();
    const std::string text = dir_.file("notes.txt");
    std::ofstream(text) << "not a database, but long enough to be read as one would be read by SQLite\n";

    EXPECT_NE(test::config_error_of([&] { merge_mission(text, recording_, archive_); }).find(text), std::string::npos);
    EXPECT_NE(test::config_error_of([&] { merge_mission(robot_log_, text, archive_); }).find(text), std::string::npos);
    const std::string swapped = test::config_error_of([&] { merge_mission(recording_, robot_log_, archive_); });
    EXPECT_NE(swapped.find("on-robot log '" + recording_ + "'"), std::string::npos) << swapped;
    const std::string missing = dir_.file("missing.db");
    EXPECT_NE(test::config_error_of([&] { merge_mission(missing, recording_, archive_); }).find(missing),
              std::string::npos);
    EXPECT_FALSE(fs::exists(archive_));
}

TEST_F(MissionArchiveTest, RefusesALogFromAGatewayThatDidNotRecordForwardedSamples) {
    write_files();
    make_the_log_older();

    const std::string message = test::config_error_of([&] { merge_mission(robot_log_, recording_, archive_); });

    EXPECT_NE(message.find(robot_log_), std::string::npos) << message;
    EXPECT_NE(message.find("forwarded"), std::string::npos) << message;
}

TEST_F(MissionArchiveTest, ALogFromAnOlderGatewayOpensAndGainsTheForwardedTable) {
    write_files();
    make_the_log_older();
    declare("telemetry/A", 1000 * MS);
    forward("telemetry/A", T0_NS, 41);
    record("telemetry/A", T0_NS, 41, 10.0);

    const MergeCounts counts = write_and_merge();

    EXPECT_EQ(counts.total.received, 1u);
    EXPECT_EQ(counts.total.received_unmatched, 0u);
}

TEST_F(MissionArchiveTest, RecordsForwardedSamplesInTheRobotLogWithoutTheirPayload) {
    declare("keyed", 1000 * MS);
    forward("keyed", T0_NS, 300, key(9));

    write_files();

    EXPECT_EQ(
        query(robot_log_, "SELECT topic, type_name, hex(instance_key), source_time_ns - " + std::to_string(T0_NS) +
                              ", arrival_ns - source_time_ns, deadline_ns - source_time_ns, forwarded_ns - arrival_ns, "
                              "payload_bytes FROM forwarded_samples"),
        (std::vector<std::string>{std::string("keyed|") + TYPE +
                                  "|09000000000000000000000000000000|0|1000000|1000000000|0|304"}));
    EXPECT_EQ(query(robot_log_, "SELECT COUNT(*) FROM dropped_samples"), (std::vector<std::string>{"0"}));
}

TEST_F(MissionArchiveTest, DoesNotReplaceAFileThatIsNotAnArchive) {
    write_files();
    std::ofstream(archive_) << "someone's notes\n";

    EXPECT_NE(test::config_error_of([&] { merge_mission(robot_log_, recording_, archive_); }).find(archive_),
              std::string::npos);
    EXPECT_NE(test::config_error_of([&] { merge_mission(robot_log_, recording_, recording_); }).find(recording_),
              std::string::npos);
    std::ifstream in(archive_);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "someone's notes");
}

TEST_F(MissionArchiveTest, AStoppedMergeLeavesThePreviousArchiveAndNoTemporaryFile) {
    declare("telemetry/A", 1000 * MS);
    forward("telemetry/A", T0_NS, 41);
    record("telemetry/A", T0_NS, 41, 10.0);
    write_and_merge();
    const std::vector<std::string> before = dump(archive_);
    forward("telemetry/A", T0_NS + 200 * MS, 41);
    write_files();
    const std::atomic<bool> stop{true};

    EXPECT_FALSE(merge_mission(robot_log_, recording_, archive_, &stop).has_value());

    EXPECT_EQ(dump(archive_), before);
    for (const auto& entry : fs::directory_iterator(dir_.path()))
        EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace tgw::basecamp
