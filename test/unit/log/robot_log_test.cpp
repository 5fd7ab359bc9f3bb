#include "gateway/log/robot_log.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "base/config_error.hpp"
#include "test/fakes/fake_clock.hpp"

namespace tgw::log {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using std::chrono::seconds;

/// One row of `dropped_samples` as read back with plain SQLite.
struct StoredRow {
    std::string topic;
    std::string type_name;
    std::vector<std::uint8_t> payload;
    std::optional<std::vector<std::uint8_t>> instance_key;
    std::int64_t source_time_ns = 0;
    std::int64_t arrival_ns = 0;
    std::int64_t deadline_ns = 0;
    std::int64_t logged_ns = 0;
    std::string reason;
};

std::vector<std::uint8_t> blob(sqlite3_stmt* stmt, int column) {
    const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt, column));
    return std::vector<std::uint8_t>(data, data + sqlite3_column_bytes(stmt, column));
}

std::string text(sqlite3_stmt* stmt, int column) {
    const auto* data = reinterpret_cast<const char*>(sqlite3_column_text(stmt, column));
    return data ? std::string(data) : std::string();
}

/// Reads a log file the way an operator would, independently of RobotLog.
class LogReader {
  public:
    explicit LogReader(const std::string& path) {
        if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK)
            ADD_FAILURE() << "cannot open " << path << ": " << sqlite3_errmsg(db_);
    }
    ~LogReader() { sqlite3_close_v2(db_); }

    std::vector<StoredRow> rows() {
        std::vector<StoredRow> out;
        sqlite3_stmt* stmt = prepare(
            "SELECT topic, type_name, payload, instance_key, source_time_ns, arrival_ns, deadline_ns, logged_ns, "
            "reason FROM dropped_samples ORDER BY id");
        while (sqlite3_step(stmt) == SQLITE_ROW) {
            StoredRow r;
            r.topic = text(stmt, 0);
            r.type_name = text(stmt, 1);
            r.payload = blob(stmt, 2);
            if (sqlite3_column_type(stmt, 3) != SQLITE_NULL)
                r.instance_key = blob(stmt, 3);
            r.source_time_ns = sqlite3_column_int64(stmt, 4);
            r.arrival_ns = sqlite3_column_int64(stmt, 5);
            r.deadline_ns = sqlite3_column_int64(stmt, 6);
            r.logged_ns = sqlite3_column_int64(stmt, 7);
            r.reason = text(stmt, 8);
            out.push_back(std::move(r));
        }
        sqlite3_finalize(stmt);
        return out;
    }

    std::string scalar(const char* sql) {
        sqlite3_stmt* stmt = prepare(sql);
        std::string value = sqlite3_step(stmt) == SQLITE_ROW ? text(stmt, 0) : "<no row>";
        sqlite3_finalize(stmt);
        return value;
    }

    std::string scalar(const std::string& sql) { return scalar(sql.c_str()); }

    std::int64_t count() { return std::stoll(scalar("SELECT COUNT(*) FROM dropped_samples")); }

    /// The ids of the rows of dropped_samples that meet `condition`, ascending.
    std::vector<std::int64_t> ids(const std::string& condition) {
        std::vector<std::int64_t> out;
        sqlite3_stmt* stmt = prepare(("SELECT id FROM dropped_samples WHERE " + condition + " ORDER BY id").c_str());
        while (sqlite3_step(stmt) == SQLITE_ROW)
            out.push_back(sqlite3_column_int64(stmt, 0));
        sqlite3_finalize(stmt);
        return out;
    }

  private:
    sqlite3_stmt* prepare(const char* sql) {
        sqlite3_stmt* stmt = nullptr;
        if (sqlite3_prepare_v2(db_, sql, -1, &stmt, nullptr) != SQLITE_OK)
            ADD_FAILURE() << sql << ": " << sqlite3_errmsg(db_);
        return stmt;
    }

    sqlite3* db_ = nullptr;
};

/// A log as the gateway wrote it before backfill, with one dropped row: the schema of robot_log.cpp then, copied
/// rather than shared, since it must stay as it was when the code's schema changes.
void write_pre_backfill_log(const std::string& path) {
    constexpr const char* SQL =
        "CREATE TABLE IF NOT EXISTS meta ("
        "  key TEXT PRIMARY KEY,"
        "  value TEXT NOT NULL);"
        "CREATE TABLE IF NOT EXISTS dropped_samples ("
        "  id INTEGER PRIMARY KEY,"
        "  topic TEXT NOT NULL,"
        "  type_name TEXT NOT NULL,"
        "  payload BLOB NOT NULL,"
        "  instance_key BLOB,"
        "  source_time_ns INTEGER NOT NULL,"
        "  arrival_ns INTEGER NOT NULL,"
        "  deadline_ns INTEGER NOT NULL,"
        "  logged_ns INTEGER NOT NULL,"
        "  reason TEXT NOT NULL);"
        "CREATE TABLE IF NOT EXISTS forwarded_samples ("
        "  id INTEGER PRIMARY KEY,"
        "  topic TEXT NOT NULL,"
        "  type_name TEXT NOT NULL,"
        "  instance_key BLOB,"
        "  source_time_ns INTEGER NOT NULL,"
        "  arrival_ns INTEGER NOT NULL,"
        "  deadline_ns INTEGER NOT NULL,"
        "  forwarded_ns INTEGER NOT NULL,"
        "  payload_bytes INTEGER NOT NULL);"
        "CREATE TABLE IF NOT EXISTS link_rates ("
        "  id INTEGER PRIMARY KEY,"
        "  time_ns INTEGER NOT NULL,"
        "  sensed_bps REAL NOT NULL,"
        "  budget_bps REAL NOT NULL);"
        "INSERT INTO meta (key, value) VALUES ('schema_version', '1');"
        "INSERT INTO dropped_samples (topic, type_name, payload, instance_key, source_time_ns, arrival_ns, "
        "deadline_ns, logged_ns, reason) VALUES ('telemetry/old', 'tgw::PaperMessage', x'0a0b0c', NULL, "
        "1700000000000000000, 1700000000100000000, 1700000001000000000, 1700000002000000000, 'expired');";
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    char* error = nullptr;
    EXPECT_EQ(sqlite3_exec(db, SQL, nullptr, nullptr, &error), SQLITE_OK) << (error ? error : "");
    sqlite3_free(error);
    sqlite3_close_v2(db);
}

std::vector<std::int64_t> row_ids(const std::vector<BackfillCandidate>& rows) {
    std::vector<std::int64_t> ids;
    for (const BackfillCandidate& row : rows)
        ids.push_back(row.row_id);
    return ids;
}

class RobotLogTest : public ::testing::Test {
  protected:
    void SetUp() override {
        std::string pattern = (fs::temp_directory_path() / "tgw-robot-log-XXXXXX").string();
        ASSERT_NE(mkdtemp(pattern.data()), nullptr);
        dir = pattern;
        path = (dir / "robot.db").string();
    }
    void TearDown() override {
        sut.reset();
        std::error_code ignored;
        fs::remove_all(dir, ignored);
    }

    core::Sample sample(std::vector<std::uint8_t> payload) {
        core::Sample s;
        s.payload = std::move(payload);
        s.source_time = clock.wall_now() - milliseconds(300);
        return s;
    }

    LogRecord record(const core::Sample& s, core::DropReason reason = core::DropReason::expired) {
        LogRecord r;
        r.topic = "telemetry/A";
        r.type_name = "tgw::PaperMessage";
        r.sample = &s;
        r.reason = reason;
        r.arrival = clock.wall_now() - milliseconds(200);
        r.deadline = clock.wall_now() + seconds(1);
        r.logged_at = clock.wall_now();
        return r;
    }

    /// Appends `n` dropped samples of `payload_bytes` each, the first byte counting them from `first`, and commits.
    void append_dropped(int n, std::size_t payload_bytes, int first = 0) {
        for (int i = first; i < first + n; ++i)
            sut->append(record(sample(std::vector<std::uint8_t>(payload_bytes, static_cast<std::uint8_t>(i)))));
        sut->flush();
    }

    /// Makes a capped log whose newest dropped row was acknowledged and pruned while older ones were kept, as
    /// the backfill of the shortest TTLs first can leave it; returns that row's id.
    std::int64_t prune_the_newest_row() {
        sut = std::make_unique<RobotLog>(path, 1u << 20);
        append_dropped(40, 10'000);
        const std::vector<std::int64_t> ids = row_ids(sut->unacknowledged(0, 100));
        EXPECT_EQ(ids.size(), 40u);
        sut->mark_acknowledged(ids[30], ids.back(), clock.wall_now());
        // Rows that take no payload push the file over its cap: the acknowledged rows go, and a few sent ones.
        const core::Sample sent = sample({1, 2, 3});
        for (int i = 0; i < 10'000; ++i)
            sut->append_forwarded({"telemetry/A", "tgw::PaperMessage", &sent, clock.wall_now(), clock.wall_now(),
                                   clock.wall_now(), std::nullopt});
        sut->flush();
        EXPECT_FALSE(sut->read_dropped(ids.back()).has_value()) << "the newest row must be pruned";
        EXPECT_TRUE(sut->read_dropped(ids[29]).has_value()) << "and the unacknowledged ones kept";
        return ids.back();
    }

    test::FakeClock clock;
    fs::path dir;
    std::string path;
    std::unique_ptr<RobotLog> sut;
};

TEST_F(RobotLogTest, StoresEveryColumnOfARecord) {
    sut = std::make_unique<RobotLog>(path);
    core::Sample s = sample({0x00, 0x01, 0x00, 0x00, 0xde, 0xad, 0x00, 0xbe, 0xef});
    s.key.valid = true;
    for (std::size_t i = 0; i < s.key.bytes.size(); ++i)
        s.key.bytes[i] = static_cast<std::uint8_t>(0xf0 + i);
    LogRecord r = record(s, core::DropReason::doomed);

    sut->append(r);
    sut->flush();

    auto rows = LogReader(path).rows();
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].topic, "telemetry/A");
    EXPECT_EQ(rows[0].type_name, "tgw::PaperMessage");
    EXPECT_EQ(rows[0].payload, s.payload);
    ASSERT_TRUE(rows[0].instance_key.has_value());
    EXPECT_EQ(*rows[0].instance_key, std::vector<std::uint8_t>(s.key.bytes.begin(), s.key.bytes.end()));
    EXPECT_EQ(rows[0].source_time_ns, base::to_ns(s.source_time));
    EXPECT_EQ(rows[0].arrival_ns, base::to_ns(r.arrival));
    EXPECT_EQ(rows[0].deadline_ns, base::to_ns(r.deadline));
    EXPECT_EQ(rows[0].logged_ns, base::to_ns(r.logged_at));
    EXPECT_EQ(rows[0].reason, "doomed");
    EXPECT_EQ(sut->rows_written(), 1u);
    EXPECT_EQ(sut->write_errors(), 0u);
}

TEST_F(RobotLogTest, StoresTheLinkRateApartFromTheSamples) {
    sut = std::make_unique<RobotLog>(path);
    const base::WallTime at = base::WallClock::now();
    sut->append_rate({at, 20'000.5, 19'000.0});
    sut->append_rate({at + std::chrono::seconds(1), 8'000.0, 7'600.0});
    sut->flush();

    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
    sqlite3_stmt* stmt = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT time_ns, sensed_bps, budget_bps FROM link_rates ORDER BY id", -1, &stmt,
                                 nullptr),
              SQLITE_OK);
    ASSERT_EQ(sqlite3_step(stmt), SQLITE_ROW);
    EXPECT_EQ(sqlite3_column_int64(stmt, 0), base::to_ns(at));
    EXPECT_EQ(sqlite3_column_double(stmt, 1), 20'000.5);
    EXPECT_EQ(sqlite3_column_double(stmt, 2), 19'000.0);
    ASSERT_EQ(sqlite3_step(stmt), SQLITE_ROW);
    EXPECT_EQ(sqlite3_column_double(stmt, 1), 8'000.0);
    EXPECT_EQ(sqlite3_step(stmt), SQLITE_DONE);
    sqlite3_finalize(stmt);
    sqlite3_close_v2(db);
    EXPECT_TRUE(LogReader(path).rows().empty()) << "a rate is not a sample";
    EXPECT_EQ(sut->rows_written(), 0u);
}

TEST_F(RobotLogTest, AtItsCapTheOldestRowsMakeRoomSentOnesFirst) {
    constexpr std::uint64_t CAP = 1u << 20;
    sut = std::make_unique<RobotLog>(path, CAP);
    const core::Sample sent = sample({1, 2, 3});
    for (int i = 0; i < 3000; ++i)
        sut->append_forwarded({"telemetry/A", "tgw::PaperMessage", &sent, clock.wall_now(), clock.wall_now(),
                               clock.wall_now(), std::nullopt});
    sut->flush();
    // 6 MB of samples not sent, 10 kB each, committed 200 kB at a time as a slow link would drop them.
    constexpr int DROPPED = 600;
    for (int i = 0; i < DROPPED; ++i) {
        const core::Sample s = sample(std::vector<std::uint8_t>(10'000, static_cast<std::uint8_t>(i)));
        sut->append(record(s));
        if (i % 20 == 19)
            sut->flush();
    }
    sut->flush();

    LogReader reader(path);
    const std::uint64_t file_bytes =
        std::stoull(reader.scalar("SELECT page_count * page_size FROM pragma_page_count(), pragma_page_size()"));
    EXPECT_LE(file_bytes, CAP + 300'000) << "the file grows past its cap by one batch at most";
    EXPECT_EQ(reader.scalar("SELECT COUNT(*) FROM forwarded_samples"), "0") << "the sent rows go first";
    EXPECT_EQ(reader.scalar("SELECT value FROM meta WHERE key = 'pruned_forwarded_rows'"), "3000");
    const std::int64_t kept = reader.count();
    const std::int64_t pruned = std::stoll(reader.scalar("SELECT value FROM meta WHERE key = 'pruned_dropped_rows'"));
    EXPECT_GT(kept, 50);
    EXPECT_EQ(kept + pruned, DROPPED);
    const auto rows = reader.rows();
    ASSERT_FALSE(rows.empty());
    EXPECT_EQ(rows.back().payload.front(), static_cast<std::uint8_t>(DROPPED - 1)) << "the newest are kept";
    EXPECT_EQ(rows.front().payload.front(), static_cast<std::uint8_t>(pruned)) << "the oldest went";
    EXPECT_EQ(sut->pruned_rows(), static_cast<std::uint64_t>(3000 + pruned));
    EXPECT_EQ(sut->write_errors(), 0u);
}

TEST_F(RobotLogTest, StoresNullInstanceKeyForUnkeyedSamples) {
    sut = std::make_unique<RobotLog>(path);
    core::Sample s = sample({1, 2, 3});

    sut->append(record(s));
    sut->flush();

    auto rows = LogReader(path).rows();
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_FALSE(rows[0].instance_key.has_value());
}

TEST_F(RobotLogTest, StoresAnEmptyPayloadAsAnEmptyBlob) {
    sut = std::make_unique<RobotLog>(path);
    core::Sample s = sample({});

    sut->append(record(s));
    sut->flush();

    auto rows = LogReader(path).rows();
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_TRUE(rows[0].payload.empty());
}

TEST_F(RobotLogTest, StoresEveryReasonByName) {
    sut = std::make_unique<RobotLog>(path);
    core::Sample s = sample({7});
    for (std::size_t i = 0; i < core::DROP_REASON_COUNT; ++i)
        sut->append(record(s, static_cast<core::DropReason>(i)));
    sut->flush();

    auto rows = LogReader(path).rows();
    ASSERT_EQ(rows.size(), core::DROP_REASON_COUNT);
    std::vector<std::string> reasons;
    for (const auto& row : rows)
        reasons.push_back(row.reason);
    EXPECT_EQ(reasons, (std::vector<std::string>{"expired", "doomed", "evicted", "oversize", "shutdown", "write_failed",
                                                 "no_reader", "rate_capped", "superseded"}));
}

TEST_F(RobotLogTest, FlushReturnsOnlyOnceEverythingAppendedIsInTheFile) {
    sut = std::make_unique<RobotLog>(path);
    core::Sample s = sample(std::vector<std::uint8_t>(100, 0x55));
    for (int i = 0; i < 2'500; ++i)
        sut->append(record(s));

    sut->flush();

    EXPECT_EQ(LogReader(path).count(), 2'500);
    EXPECT_EQ(sut->rows_written(), 2'500u);
}

TEST_F(RobotLogTest, FlushWithNothingAppendedReturnsAtOnce) {
    sut = std::make_unique<RobotLog>(path);
    sut->flush();
    EXPECT_EQ(sut->rows_written(), 0u);
}

TEST_F(RobotLogTest, DestructorWritesEverythingStillBuffered) {
    sut = std::make_unique<RobotLog>(path);
    core::Sample s = sample({1, 2, 3, 4});
    for (int i = 0; i < 1'234; ++i)
        sut->append(record(s, core::DropReason::shutdown));

    sut.reset();

    EXPECT_EQ(LogReader(path).count(), 1'234);
}

TEST_F(RobotLogTest, ReopeningAnExistingFileAppendsToIt) {
    core::Sample s = sample({9});
    {
        RobotLog first(path);
        first.append(record(s, core::DropReason::evicted));
    }
    sut = std::make_unique<RobotLog>(path);
    sut->append(record(s, core::DropReason::oversize));
    sut->flush();

    auto rows = LogReader(path).rows();
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].reason, "evicted");
    EXPECT_EQ(rows[1].reason, "oversize");
}

TEST_F(RobotLogTest, UsesWalModeAndRecordsTheSchemaVersion) {
    sut = std::make_unique<RobotLog>(path);
    LogReader reader(path);
    EXPECT_EQ(reader.scalar("PRAGMA journal_mode"), "wal");
    EXPECT_EQ(reader.scalar("SELECT value FROM meta WHERE key = 'schema_version'"), "1");
}

TEST_F(RobotLogTest, ReportsItsPath) {
    sut = std::make_unique<RobotLog>(path);
    EXPECT_EQ(sut->path(), path);
}

TEST_F(RobotLogTest, ThrowsConfigErrorNamingAPathThatCannotBeCreated) {
    const std::string bad = (dir / "no-such-dir" / "robot.db").string();
    try {
        RobotLog log(bad);
        FAIL() << "expected base::ConfigError";
    } catch (const base::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("unable to open"), std::string::npos) << e.what();
    }
}

TEST_F(RobotLogTest, ThrowsConfigErrorNamingAFileThatIsNotADatabase) {
    std::ofstream(path) << "this is not an SQLite file, but it is long enough to have a header of sorts...........";
    try {
        RobotLog log(path);
        FAIL() << "expected base::ConfigError";
    } catch (const base::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("not a database"), std::string::npos) << e.what();
    }
}

TEST_F(RobotLogTest, ThrowsConfigErrorForAnEmptyPath) {
    EXPECT_THROW(RobotLog(""), base::ConfigError);
}

TEST_F(RobotLogTest, KeepsEveryRowAppendedFromSeveralThreads) {
    sut = std::make_unique<RobotLog>(path);
    constexpr int THREADS = 4;
    constexpr int ROWS_PER_THREAD = 5'000;
    std::vector<std::thread> threads;
    for (int t = 0; t < THREADS; ++t) {
        threads.emplace_back([&, t] {
            for (int i = 0; i < ROWS_PER_THREAD; ++i) {
                core::Sample s = sample({static_cast<std::uint8_t>(t), static_cast<std::uint8_t>(i & 0xff),
                                         static_cast<std::uint8_t>(i >> 8)});
                sut->append(record(s));
            }
        });
    }
    for (auto& thread : threads)
        thread.join();
    sut->flush();

    auto rows = LogReader(path).rows();
    ASSERT_EQ(rows.size(), static_cast<std::size_t>(THREADS * ROWS_PER_THREAD));
    std::vector<std::vector<bool>> seen(THREADS, std::vector<bool>(ROWS_PER_THREAD, false));
    for (const auto& row : rows) {
        ASSERT_EQ(row.payload.size(), 3u);
        seen[row.payload[0]][row.payload[1] | (row.payload[2] << 8)] = true;
    }
    for (int t = 0; t < THREADS; ++t)
        for (int i = 0; i < ROWS_PER_THREAD; ++i)
            EXPECT_TRUE(seen[t][i]) << "thread " << t << " row " << i;
    EXPECT_EQ(sut->rows_written(), static_cast<std::uint64_t>(THREADS * ROWS_PER_THREAD));
    EXPECT_EQ(sut->write_errors(), 0u);
}

TEST_F(RobotLogTest, CommitsWithoutAFlushWithinAShortDelay) {
    sut = std::make_unique<RobotLog>(path);
    core::Sample s = sample({1});
    sut->append(record(s));

    // The writer commits a partial batch after about 50 ms; poll with a generous timeout, no fixed sleep.
    const auto give_up = std::chrono::steady_clock::now() + seconds(5);
    while (sut->rows_written() < 1 && std::chrono::steady_clock::now() < give_up)
        std::this_thread::sleep_for(milliseconds(5));
    EXPECT_EQ(sut->rows_written(), 1u);
}

// Backfill: the log's id, the migration of an older file, the reads and the marks.

TEST_F(RobotLogTest, NamesANewFileWithARandomIdThatStaysAcrossReopening) {
    std::string id;
    {
        RobotLog first(path);
        id = first.log_id();
    }
    EXPECT_EQ(id.size(), 32u);
    EXPECT_TRUE(std::all_of(id.begin(), id.end(), [](char c) {
        return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
    })) << id;

    sut = std::make_unique<RobotLog>(path);
    EXPECT_EQ(sut->log_id(), id);
    EXPECT_EQ(LogReader(path).scalar("SELECT value FROM meta WHERE key = 'log_id'"), id);
    EXPECT_NE(RobotLog((dir / "other.db").string()).log_id(), id) << "another file, another id";
}

TEST_F(RobotLogTest, OpensALogFromBeforeBackfillKeepingItsRowAndAddingTheColumnsAndAnId) {
    write_pre_backfill_log(path);

    sut = std::make_unique<RobotLog>(path);

    EXPECT_EQ(sut->log_id().size(), 32u);
    {
        LogReader reader(path);
        EXPECT_EQ(reader.scalar("SELECT COUNT(*) FROM pragma_table_info('dropped_samples') "
                                "WHERE name IN ('acked_ns', 'sends', 'last_sent_ns', 'kind')"),
                  "4");
        EXPECT_EQ(reader.scalar("SELECT (acked_ns IS NULL) || ',' || sends || ',' || (last_sent_ns IS NULL) || ',' "
                                "|| kind FROM dropped_samples"),
                  "1,0,1,data");
        EXPECT_EQ(reader.scalar("SELECT value FROM meta WHERE key = 'log_id'"), sut->log_id());
    }
    const std::vector<BackfillCandidate> rows = sut->unacknowledged(0, 10);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].topic, "telemetry/old");
    EXPECT_EQ(base::to_ns(rows[0].source_time), 1'700'000'000'000'000'000);
    EXPECT_EQ(base::to_ns(rows[0].deadline), 1'700'000'001'000'000'000);
    EXPECT_EQ(rows[0].payload_bytes, 3u);

    // The migrated file takes new rows, after the old one.
    append_dropped(1, 5);
    const std::vector<BackfillCandidate> after = sut->unacknowledged(0, 10);
    ASSERT_EQ(after.size(), 2u);
    EXPECT_EQ(after[0].row_id, rows[0].row_id);
    EXPECT_EQ(after[1].payload_bytes, 5u);

    const std::string id = sut->log_id();
    sut = std::make_unique<RobotLog>(path);
    EXPECT_EQ(sut->log_id(), id) << "made once, on the first reopening";
}

TEST_F(RobotLogTest, ListsTheUnacknowledgedRowsByIdAPageAtATime) {
    sut = std::make_unique<RobotLog>(path);
    for (std::size_t i = 1; i <= 5; ++i)
        append_dropped(1, i);
    const core::Sample s = sample({});
    const LogRecord r = record(s);
    const std::vector<BackfillCandidate> all = sut->unacknowledged(0, 100);
    ASSERT_EQ(all.size(), 5u);
    EXPECT_TRUE(
        std::is_sorted(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.row_id < b.row_id; }));
    for (std::size_t i = 0; i < all.size(); ++i) {
        EXPECT_EQ(all[i].topic, "telemetry/A");
        EXPECT_EQ(all[i].payload_bytes, i + 1);
        EXPECT_EQ(all[i].source_time, s.source_time);
        EXPECT_EQ(all[i].deadline, r.deadline);
    }

    EXPECT_EQ(row_ids(sut->unacknowledged(0, 2)), (std::vector<std::int64_t>{all[0].row_id, all[1].row_id}));
    EXPECT_EQ(row_ids(sut->unacknowledged(all[1].row_id, 2)),
              (std::vector<std::int64_t>{all[2].row_id, all[3].row_id}));
    EXPECT_EQ(row_ids(sut->unacknowledged(all[3].row_id, 2)), (std::vector<std::int64_t>{all[4].row_id}));
    EXPECT_TRUE(sut->unacknowledged(all[4].row_id, 2).empty());
    EXPECT_TRUE(sut->unacknowledged(0, 0).empty());
}

TEST_F(RobotLogTest, KeepsADisposeOutOfBackfillAndReadsItBackAsOne) {
    sut = std::make_unique<RobotLog>(path);
    core::Sample dispose = sample({});
    dispose.kind = core::SampleKind::dispose;
    dispose.key.valid = true;
    dispose.key.bytes.fill(0x42);
    sut->append(record(dispose));
    append_dropped(1, 3);
    sut->flush();

    // The camp records no dispose live: backfill sends the data row only.
    const std::vector<BackfillCandidate> rows = sut->unacknowledged(0, 10);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].payload_bytes, 3u);
    EXPECT_EQ(LogReader(path).scalar("SELECT group_concat(kind) FROM (SELECT kind FROM dropped_samples ORDER BY id)"),
              "dispose,data");

    const std::int64_t dispose_row = std::stoll(LogReader(path).scalar("SELECT MIN(id) FROM dropped_samples"));
    const std::optional<StoredSample> stored = sut->read_dropped(dispose_row);
    ASSERT_TRUE(stored.has_value());
    EXPECT_EQ(stored->kind, core::SampleKind::dispose);
    EXPECT_TRUE(stored->payload.empty());
    EXPECT_TRUE(stored->key.valid);
    EXPECT_EQ(stored->key.bytes, dispose.key.bytes);
    EXPECT_EQ(sut->read_dropped(rows[0].row_id)->kind, core::SampleKind::data);
}

TEST_F(RobotLogTest, LeavesTheRowsTheCampAcknowledgedOutOfTheList) {
    sut = std::make_unique<RobotLog>(path);
    append_dropped(5, 10);
    const std::vector<std::int64_t> ids = row_ids(sut->unacknowledged(0, 10));
    ASSERT_EQ(ids.size(), 5u);
    const base::WallTime first_ack = clock.wall_now();

    sut->mark_acknowledged(ids[1], ids[2], first_ack);
    sut->flush();

    EXPECT_EQ(row_ids(sut->unacknowledged(0, 10)), (std::vector<std::int64_t>{ids[0], ids[3], ids[4]}));
    EXPECT_EQ(sut->acknowledged_rows(), 2u);
    const std::string acked_ns_of_second = "SELECT acked_ns FROM dropped_samples WHERE id = " + std::to_string(ids[1]);
    EXPECT_EQ(LogReader(path).scalar(acked_ns_of_second), std::to_string(base::to_ns(first_ack)));

    // An acknowledgement that overlaps one already made counts only the new row and keeps the first time.
    clock.advance(seconds(3));
    sut->mark_acknowledged(ids[0], ids[2], clock.wall_now());
    sut->flush();

    EXPECT_EQ(row_ids(sut->unacknowledged(0, 10)), (std::vector<std::int64_t>{ids[3], ids[4]}));
    EXPECT_EQ(sut->acknowledged_rows(), 3u);
    EXPECT_EQ(LogReader(path).scalar(acked_ns_of_second), std::to_string(base::to_ns(first_ack)));
    EXPECT_EQ(sut->write_errors(), 0u);
}

TEST_F(RobotLogTest, ReadsADroppedRowBackAsItWasAppended) {
    sut = std::make_unique<RobotLog>(path);
    core::Sample s = sample({0x00, 0x01, 0x00, 0x00, 0xca, 0xfe});
    s.key.valid = true;
    for (std::size_t i = 0; i < s.key.bytes.size(); ++i)
        s.key.bytes[i] = static_cast<std::uint8_t>(0xa0 + i);
    LogRecord r = record(s, core::DropReason::doomed);
    r.topic = "telemetry/B";
    r.type_name = "tgw::Pose";
    sut->append(r);
    sut->flush();
    const std::vector<BackfillCandidate> rows = sut->unacknowledged(0, 1);
    ASSERT_EQ(rows.size(), 1u);

    const std::optional<StoredSample> stored = sut->read_dropped(rows[0].row_id);

    ASSERT_TRUE(stored.has_value());
    EXPECT_EQ(stored->row_id, rows[0].row_id);
    EXPECT_EQ(stored->topic, "telemetry/B");
    EXPECT_EQ(stored->type_name, "tgw::Pose");
    EXPECT_EQ(stored->payload, s.payload);
    EXPECT_TRUE(stored->key.valid);
    EXPECT_EQ(stored->key.bytes, s.key.bytes);
    EXPECT_EQ(stored->kind, core::SampleKind::data);
    EXPECT_EQ(stored->source_time, s.source_time);
    EXPECT_EQ(stored->deadline, r.deadline);
    EXPECT_EQ(stored->reason, "doomed");
    EXPECT_FALSE(sut->read_dropped(rows[0].row_id + 1).has_value()) << "no such row";
}

TEST_F(RobotLogTest, CountsEachSendOfARowAndKeepsTheTimeOfTheLast) {
    sut = std::make_unique<RobotLog>(path);
    append_dropped(2, 10);
    const std::vector<std::int64_t> ids = row_ids(sut->unacknowledged(0, 10));
    ASSERT_EQ(ids.size(), 2u);

    sut->mark_sent(ids[0], clock.wall_now());
    clock.advance(seconds(7));
    const base::WallTime second_send = clock.wall_now();
    sut->mark_sent(ids[0], second_send);
    sut->flush();

    LogReader reader(path);
    const std::string where = " FROM dropped_samples WHERE id = ";
    EXPECT_EQ(reader.scalar("SELECT sends" + where + std::to_string(ids[0])), "2");
    EXPECT_EQ(reader.scalar("SELECT last_sent_ns" + where + std::to_string(ids[0])),
              std::to_string(base::to_ns(second_send)));
    EXPECT_EQ(reader.scalar("SELECT sends || ',' || (last_sent_ns IS NULL)" + where + std::to_string(ids[1])), "0,1");
    EXPECT_EQ(sut->unacknowledged(0, 10).size(), 2u) << "sent is not acknowledged";
}

TEST_F(RobotLogTest, MarksOfRowsThatAreGoneChangeNothingAndAreNoErrors) {
    sut = std::make_unique<RobotLog>(path);
    append_dropped(1, 10);

    sut->mark_sent(1'000, clock.wall_now());
    sut->mark_acknowledged(1'000, 2'000, clock.wall_now());
    sut->flush();

    EXPECT_EQ(sut->write_errors(), 0u);
    EXPECT_EQ(sut->acknowledged_rows(), 0u);
    EXPECT_EQ(LogReader(path).scalar("SELECT SUM(sends) || ',' || COUNT(acked_ns) FROM dropped_samples"), "0,0");
}

TEST_F(RobotLogTest, ListsCommittedRowsWhileTheWriterAppends) {
    sut = std::make_unique<RobotLog>(path);
    constexpr int ROWS = 3'000;
    std::atomic<bool> appended{false};
    std::thread writer([&] {
        for (int i = 0; i < ROWS; i += 100)
            append_dropped(100, 64, i);
        appended = true;
    });

    std::int64_t last = 0;
    int seen = 0;
    bool ascending = true;
    for (;;) {
        const bool finished = appended;  // read before the page: then the page holds every row
        const std::vector<BackfillCandidate> page = sut->unacknowledged(last, 256);
        for (const BackfillCandidate& row : page) {
            ascending = ascending && row.row_id > last;
            last = row.row_id;
            seen += row.payload_bytes == 64 ? 1 : 0;
        }
        if (finished && page.empty())
            break;
        std::this_thread::yield();
    }
    writer.join();

    EXPECT_EQ(seen, ROWS);
    EXPECT_TRUE(ascending);
    EXPECT_EQ(sut->write_errors(), 0u);
}

TEST_F(RobotLogTest, AtItsCapTheAcknowledgedRowsGoFirstThenTheSentOnesThenTheRest) {
    constexpr std::uint64_t CAP = 1u << 20;
    constexpr std::size_t ROW_BYTES = 10'000;
    sut = std::make_unique<RobotLog>(path, CAP);
    // 40 samples not sent; the camp acknowledges every other one, so that the acknowledged rows are not simply
    // the oldest.
    append_dropped(40, ROW_BYTES);
    const std::vector<std::int64_t> first = row_ids(sut->unacknowledged(0, 100));
    ASSERT_EQ(first.size(), 40u);
    for (std::size_t i = 1; i < first.size(); i += 2)
        sut->mark_acknowledged(first[i], first[i], clock.wall_now());
    const core::Sample sent = sample({1, 2, 3});
    constexpr int FORWARDED = 2'000;
    for (int i = 0; i < FORWARDED; ++i)
        sut->append_forwarded({"telemetry/A", "tgw::PaperMessage", &sent, clock.wall_now(), clock.wall_now(),
                               clock.wall_now(), std::nullopt});
    sut->flush();
    ASSERT_EQ(sut->acknowledged_rows(), 20u);
    ASSERT_EQ(sut->pruned_rows(), 0u) << "under the cap so far";
    const std::vector<std::int64_t> acked = LogReader(path).ids("acked_ns IS NOT NULL");
    ASSERT_EQ(acked.size(), 20u);

    // Then more samples not sent, a few at a time, until every kind of row has had to go.
    constexpr int MORE = 100;
    for (int i = 0; i < MORE; i += 5) {
        append_dropped(5, ROW_BYTES, 40 + i);
        LogReader reader(path);
        const std::vector<std::int64_t> acked_left = reader.ids("acked_ns IS NOT NULL");
        const std::int64_t forwarded_left = std::stoll(reader.scalar("SELECT COUNT(*) FROM forwarded_samples"));
        EXPECT_TRUE(std::equal(acked_left.begin(), acked_left.end(), acked.end() - acked_left.size()))
            << "the oldest acknowledged rows go first";
        if (forwarded_left < FORWARDED) {
            EXPECT_TRUE(acked_left.empty()) << "a sent row went while an acknowledged one was left, after " << i;
        }
        const std::int64_t unacknowledged_left = reader.count() - static_cast<std::int64_t>(acked_left.size());
        if (unacknowledged_left < 20 + i + 5) {
            EXPECT_TRUE(acked_left.empty()) << "an unacknowledged row went before the acknowledged ones, after " << i;
            EXPECT_EQ(forwarded_left, 0) << "an unacknowledged row went before the sent ones, after " << i;
        }
    }

    LogReader reader(path);
    EXPECT_EQ(reader.scalar("SELECT value FROM meta WHERE key = 'pruned_acknowledged_rows'"), "20");
    EXPECT_EQ(reader.scalar("SELECT value FROM meta WHERE key = 'pruned_forwarded_rows'"), std::to_string(FORWARDED));
    const std::int64_t pruned_dropped =
        std::stoll(reader.scalar("SELECT value FROM meta WHERE key = 'pruned_dropped_rows'"));
    EXPECT_GT(pruned_dropped, 0) << "the cap was reached again once the others were gone";
    // The unacknowledged rows left are the newest: the 20 first ones and all MORE, less the oldest pruned.
    const auto rows = reader.rows();
    EXPECT_EQ(static_cast<std::int64_t>(rows.size()) + pruned_dropped, 20 + MORE);
    ASSERT_FALSE(rows.empty());
    EXPECT_EQ(rows.back().payload.front(), static_cast<std::uint8_t>(40 + MORE - 1));
    EXPECT_EQ(sut->pruned_rows(), static_cast<std::uint64_t>(20 + FORWARDED + pruned_dropped));
    EXPECT_EQ(sut->write_errors(), 0u);
}

TEST_F(RobotLogTest, NeverGivesTheIdOfAPrunedRowAgain) {
    const std::int64_t pruned = prune_the_newest_row();

    append_dropped(1, 10, 200);

    const std::vector<BackfillCandidate> rows = sut->unacknowledged(0, 100);
    ASSERT_FALSE(rows.empty());
    EXPECT_GT(rows.back().row_id, pruned);
}

TEST_F(RobotLogTest, NeverGivesTheIdOfAPrunedRowAgainAfterReopening) {
    const std::int64_t pruned = prune_the_newest_row();
    sut = std::make_unique<RobotLog>(path);

    append_dropped(1, 10, 200);

    const std::vector<BackfillCandidate> rows = sut->unacknowledged(0, 100);
    ASSERT_FALSE(rows.empty());
    EXPECT_GT(rows.back().row_id, pruned);
}

}  // namespace
}  // namespace tgw::log
