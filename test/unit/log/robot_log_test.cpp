#include "gateway/log/robot_log.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

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

    std::int64_t count() { return std::stoll(scalar("SELECT COUNT(*) FROM dropped_samples")); }

  private:
    sqlite3_stmt* prepare(const char* sql) {
        sqlite3_stmt* stmt = nullptr;
        if (sqlite3_prepare_v2(db_, sql, -1, &stmt, nullptr) != SQLITE_OK)
            ADD_FAILURE() << sql << ": " << sqlite3_errmsg(db_);
        return stmt;
    }

    sqlite3* db_ = nullptr;
};

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
        sut->append_forwarded(
            {"telemetry/A", "tgw::PaperMessage", &sent, clock.wall_now(), clock.wall_now(), clock.wall_now()});
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
                                                 "no_reader"}));
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

}  // namespace
}  // namespace tgw::log
