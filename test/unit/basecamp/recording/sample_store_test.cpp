// The camp's recording (SampleStore's SQLite file) with backfill: rows from the on-robot log stored once, flagged,
// and acknowledged only after their commit; live samples as before; an older recording migrated when opened.
#include "basecamp/recording/sample_store.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <chrono>
#include <cstdint>
#include <future>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "test/unit/basecamp/scratch_dir.hpp"

namespace tgw::basecamp {
namespace {

constexpr std::int64_t T0_NS = 1'800'000'000'000'000'000;
constexpr std::int64_t S = 1'000'000'000;
const std::string LOG_ID = "0123456789abcdef0123456789abcdef";

/// The samples table as SampleStore created it before backfill, word for word: a copy on purpose, since the
/// code's may change and an old file's does not.
constexpr const char* OLD_SAMPLES_TABLE = R"sql(
CREATE TABLE IF NOT EXISTS samples(
    id INTEGER PRIMARY KEY,
    topic TEXT NOT NULL,
    type_name TEXT NOT NULL,
    payload BLOB NOT NULL,
    source_ns INTEGER NOT NULL,
    receive_ns INTEGER NOT NULL,
    lifespan_ns INTEGER,
    instance BLOB);
)sql";

SampleRecord live(std::int64_t source_s) {
    SampleRecord s;
    s.topic = "rt/pose";
    s.type_name = "geometry_msgs::msg::dds_::Pose_";
    s.payload = {0x00, 0x01, 0x00, 0x00, 0x2a};
    s.source_ns = T0_NS + source_s * S;
    s.receive_ns = s.source_ns + S / 10;
    s.lifespan_ns = 2 * S;
    return s;
}

/// Row `row_id` of the robot's log, sent `source_s` after T0 and arriving at the camp 60 s later.
SampleRecord backfilled(std::int64_t row_id, std::int64_t source_s, const std::string& reason = "expired") {
    SampleRecord s = live(source_s);
    s.receive_ns = s.source_ns + 60 * S;
    s.backfill = BackfillOrigin{LOG_ID, row_id, reason};
    return s;
}

/// Runs one SQL query on its own connection and gives each row as text, columns joined with '|', NULL as "NULL".
std::vector<std::string> rows_of(const std::string& path, const std::string& sql) {
    sqlite3* db = nullptr;
    std::vector<std::string> rows;
    if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
        ADD_FAILURE() << "cannot open " << path;
        sqlite3_close(db);
        return rows;
    }
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr) != SQLITE_OK)
        ADD_FAILURE() << sql << ": " << sqlite3_errmsg(db);
    while (stmt != nullptr && sqlite3_step(stmt) == SQLITE_ROW) {
        std::string row;
        for (int i = 0; i < sqlite3_column_count(stmt); ++i) {
            const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt, i));
            row += (i > 0 ? "|" : "") + std::string(text != nullptr ? text : "NULL");
        }
        rows.push_back(std::move(row));
    }
    sqlite3_finalize(stmt);
    sqlite3_close(db);
    return rows;
}

class SampleStoreTest : public ::testing::Test {
  protected:
    /// Records each acknowledgement the store gives (on its writer thread).
    void listen(SampleStore& sut) {
        sut.on_backfill_stored([this](const std::string& log_id, std::int64_t row_id) {
            std::lock_guard<std::mutex> lock(mutex_);
            acknowledged_.emplace_back(log_id, row_id);
        });
    }

    std::vector<std::pair<std::string, std::int64_t>> acknowledged() {
        std::lock_guard<std::mutex> lock(mutex_);
        return acknowledged_;
    }

    /// The backfill columns and times of every sample, in id order.
    std::vector<std::string> stored() const {
        return rows_of(recording_,
                       "SELECT topic, source_ns, receive_ns, lifespan_ns, backfilled, log_id, row_id, "
                       "drop_reason FROM samples ORDER BY id");
    }

    /// The layout of samples and its indexes, as a new and a migrated file must share it.
    std::vector<std::string> layout(const std::string& path) const {
        std::vector<std::string> out = rows_of(path,
                                               "SELECT cid, name, type, \"notnull\", dflt_value, pk "
                                               "FROM pragma_table_info('samples') ORDER BY cid");
        for (std::string& index : rows_of(path,
                                          "SELECT name, sql FROM sqlite_master WHERE type = 'index' AND "
                                          "tbl_name = 'samples' ORDER BY name"))
            out.push_back(std::move(index));
        return out;
    }

    test::ScratchDir dir_{"tgw-sample-store"};
    const std::string recording_ = dir_.file("camp.db");
    std::mutex mutex_;
    std::vector<std::pair<std::string, std::int64_t>> acknowledged_;
};

TEST_F(SampleStoreTest, StoresABackfilledRowWithItsFlagOriginReasonAndTimes) {
    SampleStore sut(recording_, "--out", 10);
    listen(sut);
    sut.add(backfilled(7, 3, "doomed"));
    sut.flush();

    const std::int64_t source_ns = T0_NS + 3 * S;
    EXPECT_EQ(stored(), (std::vector<std::string>{"rt/pose|" + std::to_string(source_ns) + "|" +
                                                  std::to_string(source_ns + 60 * S) + "|" + std::to_string(2 * S) +
                                                  "|1|" + LOG_ID + "|7|doomed"}));
    EXPECT_EQ(rows_of(recording_, "SELECT hex(payload), instance FROM samples"),
              (std::vector<std::string>{"000100002A|NULL"}));
    EXPECT_EQ(sut.rows_written(), 1u);
    EXPECT_EQ(sut.duplicate_backfill_rows(), 0u);
    EXPECT_EQ(sut.write_errors(), 0u);
    EXPECT_EQ(acknowledged(), (std::vector<std::pair<std::string, std::int64_t>>{{LOG_ID, 7}}));
}

TEST_F(SampleStoreTest, StoresARowSentTwiceOnceAndAcknowledgesItEachTime) {
    {
        SampleStore sut(recording_, "--out", 10);
        listen(sut);
        sut.add(backfilled(7, 3));
        sut.add(backfilled(8, 4));
        sut.flush();
        sut.add(backfilled(7, 3));  // a resend after a lost acknowledgement
        sut.flush();
        EXPECT_EQ(sut.rows_written(), 2u);
        EXPECT_EQ(sut.duplicate_backfill_rows(), 1u);
        EXPECT_EQ(sut.write_errors(), 0u);
    }
    {
        // A restarted gateway sends it again, to a camp restarted meanwhile; in one batch with its twin too.
        SampleStore sut(recording_, "--out", 10);
        listen(sut);
        sut.add(backfilled(7, 3));
        sut.add(backfilled(9, 5));
        sut.add(backfilled(9, 5));
        sut.flush();
        EXPECT_EQ(sut.rows_written(), 1u);
        EXPECT_EQ(sut.duplicate_backfill_rows(), 2u);
        EXPECT_EQ(sut.write_errors(), 0u);
    }
    EXPECT_EQ(rows_of(recording_, "SELECT row_id, COUNT(*) FROM samples GROUP BY row_id ORDER BY row_id"),
              (std::vector<std::string>{"7|1", "8|1", "9|1"}));
    EXPECT_EQ(acknowledged(), (std::vector<std::pair<std::string, std::int64_t>>{
                                  {LOG_ID, 7}, {LOG_ID, 8}, {LOG_ID, 7}, {LOG_ID, 7}, {LOG_ID, 9}, {LOG_ID, 9}}));
}

TEST_F(SampleStoreTest, TellsRowsOfTwoLogsApartByTheirLogId) {
    SampleStore sut(recording_, "--out", 10);
    sut.add(backfilled(7, 3));
    SampleRecord other = backfilled(7, 3);
    other.backfill->log_id = "fedcba9876543210fedcba9876543210";  // another robot's log, or a new log
    sut.add(other);
    sut.flush();

    EXPECT_EQ(rows_of(recording_, "SELECT log_id, row_id FROM samples ORDER BY id"),
              (std::vector<std::string>{LOG_ID + "|7", "fedcba9876543210fedcba9876543210|7"}));
    EXPECT_EQ(sut.duplicate_backfill_rows(), 0u);
}

TEST_F(SampleStoreTest, StoresLiveSamplesAsBeforeAndNeverAcknowledgesThem) {
    SampleStore sut(recording_, "--out", 10);
    listen(sut);
    sut.add(live(1));
    sut.add(live(1));  // two live samples alike are two samples
    sut.add(backfilled(7, 0));
    sut.add(live(2));
    sut.flush();

    const auto row = [](std::int64_t source_s) {
        const std::int64_t source_ns = T0_NS + source_s * S;
        return "rt/pose|" + std::to_string(source_ns) + "|" + std::to_string(source_ns + S / 10) + "|" +
               std::to_string(2 * S) + "|0|NULL|NULL|NULL";
    };
    const std::vector<std::string> rows = stored();
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(rows[0], row(1));
    EXPECT_EQ(rows[1], row(1));
    EXPECT_EQ(rows[3], row(2));
    EXPECT_EQ(sut.rows_written(), 4u);
    EXPECT_EQ(sut.duplicate_backfill_rows(), 0u);
    EXPECT_EQ(acknowledged(), (std::vector<std::pair<std::string, std::int64_t>>{{LOG_ID, 7}}));
}

TEST_F(SampleStoreTest, AcknowledgesARowOnlyOnceAnotherConnectionCanReadIt) {
    SampleStore sut(recording_, "--out", 10);
    std::vector<std::string> seen;  // written by the store's writer thread, read after flush()
    sut.on_backfill_stored([&](const std::string& log_id, std::int64_t row_id) {
        const std::vector<std::string> rows =
            rows_of(recording_, "SELECT COUNT(*) FROM samples WHERE log_id = '" + log_id +
                                    "' AND row_id = " + std::to_string(row_id));
        seen.push_back(std::to_string(row_id) + ":" + (rows.empty() ? "none" : rows[0]));
    });
    for (std::int64_t row_id = 1; row_id <= 50; ++row_id)
        sut.add(backfilled(row_id, row_id));
    sut.flush();
    sut.add(backfilled(20, 20));  // a duplicate, acknowledged once its (empty) write has committed too
    sut.flush();

    ASSERT_EQ(seen.size(), 51u);
    for (std::int64_t row_id = 1; row_id <= 50; ++row_id)
        EXPECT_EQ(seen[static_cast<std::size_t>(row_id - 1)], std::to_string(row_id) + ":1");
    EXPECT_EQ(seen[50], "20:1");
}

TEST_F(SampleStoreTest, DoesNotAcknowledgeARowItCouldNotStore) {
    SampleStore sut(recording_, "--out", 10);
    listen(sut);
    sqlite3* other = nullptr;
    ASSERT_EQ(sqlite3_open(recording_.c_str(), &other), SQLITE_OK);
    // Another writer holds the file: the store's insert fails at once (it sets no busy timeout).
    ASSERT_EQ(sqlite3_exec(other, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr), SQLITE_OK);
    sut.add(backfilled(7, 3));
    sut.flush();
    EXPECT_EQ(sqlite3_exec(other, "COMMIT", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(other);

    EXPECT_TRUE(acknowledged().empty());
    EXPECT_EQ(sut.write_errors(), 1u);
    EXPECT_EQ(sut.rows_written(), 0u);
    EXPECT_TRUE(stored().empty());

    sut.add(backfilled(7, 3));  // the robot's resend
    sut.flush();
    EXPECT_EQ(stored().size(), 1u);
    EXPECT_EQ(sut.duplicate_backfill_rows(), 0u) << "the first was never stored";
    EXPECT_EQ(acknowledged(), (std::vector<std::pair<std::string, std::int64_t>>{{LOG_ID, 7}}));
}

TEST_F(SampleStoreTest, AnAcknowledgementDoesNotBlockAnotherThreadsAdd) {
    SampleStore sut(recording_, "--out", 10);
    // As the relay's acknowledgement, a DDS write, may wait on a DDS thread that is in add() at that moment.
    std::thread dds_thread;
    bool added_meanwhile = false;
    sut.on_backfill_stored([&](const std::string&, std::int64_t row_id) {
        if (row_id != 7)
            return;
        std::promise<void> added;
        std::future<void> done = added.get_future();
        dds_thread = std::thread([&sut, added = std::move(added)]() mutable {
            sut.add(backfilled(8, 4));
            added.set_value();
        });
        added_meanwhile = done.wait_for(std::chrono::seconds(10)) == std::future_status::ready;
    });
    sut.add(backfilled(7, 3));
    sut.flush();  // returns once 7 is acknowledged
    dds_thread.join();
    sut.flush();

    EXPECT_TRUE(added_meanwhile) << "add() waited for a lock held while acknowledging";
    EXPECT_EQ(rows_of(recording_, "SELECT row_id FROM samples ORDER BY id"), (std::vector<std::string>{"7", "8"}));
}

TEST_F(SampleStoreTest, OpensAnOlderRecordingKeepsItsRowsAndGainsTheBackfillColumns) {
    const std::string old_file = dir_.file("old.db");
    {
        sqlite3* db = nullptr;
        ASSERT_EQ(sqlite3_open(old_file.c_str(), &db), SQLITE_OK);
        ASSERT_EQ(sqlite3_exec(db, OLD_SAMPLES_TABLE, nullptr, nullptr, nullptr), SQLITE_OK);
        ASSERT_EQ(sqlite3_exec(db,
                               "INSERT INTO samples(topic, type_name, payload, source_ns, receive_ns, lifespan_ns, "
                               "instance) VALUES('rt/old', 'Old_', x'0001000001', 100, 200, NULL, x'01')",
                               nullptr, nullptr, nullptr),
                  SQLITE_OK);
        sqlite3_close(db);
    }
    {
        SampleStore sut(old_file, "--out", 10);
        listen(sut);
        sut.add(backfilled(7, 3));
        sut.add(backfilled(7, 3));
        sut.flush();
        EXPECT_EQ(sut.rows_written(), 1u);
        EXPECT_EQ(sut.duplicate_backfill_rows(), 1u) << "the migrated file has the unique index";
    }
    const std::vector<std::string> rows =
        rows_of(old_file,
                "SELECT id, topic, type_name, hex(payload), source_ns, receive_ns, lifespan_ns, "
                "hex(instance), backfilled, log_id, row_id, drop_reason FROM samples ORDER BY id");
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0], "1|rt/old|Old_|0001000001|100|200|NULL|01|0|NULL|NULL|NULL");
    EXPECT_EQ(rows[1].substr(0, 2), "2|");
    EXPECT_EQ(acknowledged(), (std::vector<std::pair<std::string, std::int64_t>>{{LOG_ID, 7}, {LOG_ID, 7}}));

    { SampleStore fresh(recording_, "--out", 10); }
    const std::vector<std::string> expected = layout(recording_);
    EXPECT_EQ(expected.size(), 13u) << "12 columns and the index";
    EXPECT_EQ(layout(old_file), expected);
    { SampleStore again(old_file, "--out", 10); }
    EXPECT_EQ(layout(old_file), expected) << "opened again, it stays as it is";
}

}  // namespace
}  // namespace tgw::basecamp
