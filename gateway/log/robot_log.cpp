#include "gateway/log/robot_log.hpp"

#include <sqlite3.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "base/config_error.hpp"

namespace tgw::log {

namespace {

constexpr int SCHEMA_VERSION = 1;
/// A batch is committed when it holds this many rows, or when its oldest row has waited BATCH_DELAY.
constexpr std::size_t BATCH_ROWS = 1000;
constexpr auto BATCH_DELAY = std::chrono::milliseconds(50);
/// Past this much buffered payload (the disk stalled, or is far slower than the drops), further rows are
/// refused and counted as write errors rather than letting the gateway run out of memory. A forwarded row has
/// no payload and counts for its own size instead.
constexpr std::size_t MAX_BUFFERED_BYTES = std::size_t{256} << 20;
/// How long a write waits for a reader of the file (sqlite3, tm-basecamp) to let go of a lock.
constexpr int BUSY_TIMEOUT_MS = 2000;
/// Rows deleted per statement while the file is over its cap: few, so that large rows do not take the file far
/// below the cap.
constexpr int PRUNE_ROWS = 16;

constexpr const char* SCHEMA_SQL =
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
    // Added after the first logs were written: IF NOT EXISTS gives an older file the table when it is reopened.
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
    // The link rate the gateway planned with, over time: where the robot's radio was weak, which the base camp
    // cannot hear (tm-basecamp linkmap).
    "CREATE TABLE IF NOT EXISTS link_rates ("
    "  id INTEGER PRIMARY KEY,"
    "  time_ns INTEGER NOT NULL,"
    "  sensed_bps REAL NOT NULL,"
    "  budget_bps REAL NOT NULL);";

constexpr const char* INSERT_SQL =
    "INSERT INTO dropped_samples (topic, type_name, payload, instance_key, source_time_ns, arrival_ns, "
    "deadline_ns, logged_ns, reason) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9);";

constexpr const char* INSERT_FORWARDED_SQL =
    "INSERT INTO forwarded_samples (topic, type_name, instance_key, source_time_ns, arrival_ns, deadline_ns, "
    "forwarded_ns, payload_bytes) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8);";

constexpr const char* INSERT_RATE_SQL = "INSERT INTO link_rates (time_ns, sensed_bps, budget_bps) VALUES (?1, ?2, ?3);";

struct DbCloser {
    void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};
struct StmtFinalizer {
    void operator()(sqlite3_stmt* stmt) const { sqlite3_finalize(stmt); }
};
using DbPtr = std::unique_ptr<sqlite3, DbCloser>;
using StmtPtr = std::unique_ptr<sqlite3_stmt, StmtFinalizer>;

/// A record copied out of the caller's sample, owned by the buffer: a dropped sample, a forwarded one, or a rate.
struct Row {
    enum class Kind { dropped, forwarded, rate };
    Kind kind = Kind::dropped;
    std::string topic;
    std::string type_name;
    std::vector<std::uint8_t> payload;  ///< dropped rows only
    std::size_t payload_bytes = 0;      ///< forwarded rows only
    std::optional<core::InstanceKey> key;
    std::int64_t source_time_ns = 0;
    std::int64_t arrival_ns = 0;
    std::int64_t deadline_ns = 0;
    std::int64_t logged_ns = 0;  ///< dropped: when logged; forwarded: when written to the WAN; rate: its time
    core::DropReason reason = core::DropReason::expired;
    double sensed_bps = 0, budget_bps = 0;  ///< rate rows only
};

}  // namespace

class RobotLog::Impl {
  public:
    Impl(const std::string& path, std::uint64_t max_bytes) : path_(path), max_bytes_(max_bytes) {
        open();
        writer_ = std::thread([this] { run(); });
    }

    ~Impl() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
        }
        wake_writer_.notify_one();
        writer_.join();  // the writer commits everything still buffered before it returns
        insert_.reset();
        insert_forwarded_.reset();
        insert_rate_.reset();
        db_.reset();
        if (write_errors_ > 0)
            std::fprintf(stderr, "on-robot log %s: %llu row(s) could not be written\n", path_.c_str(),
                         static_cast<unsigned long long>(write_errors_));
    }

    void append(const LogRecord& record) noexcept {
        try {
            Row row = common_row(record.topic, record.type_name, record.sample, record.arrival, record.deadline,
                                 record.logged_at);
            if (record.sample != nullptr)
                row.payload = record.sample->payload;
            row.reason = record.reason;
            const std::size_t payload_bytes = row.payload.size();
            enqueue(std::move(row), payload_bytes);
        } catch (const std::exception& e) {
            // Only allocation can fail here, before the row reached the buffer: it is lost, counted, reported once.
            fail_rows(1, e.what());
        }
    }

    void append_forwarded(const ForwardRecord& record) noexcept {
        try {
            Row row = common_row(record.topic, record.type_name, record.sample, record.arrival, record.deadline,
                                 record.forwarded_at);
            row.kind = Row::Kind::forwarded;
            if (record.sample != nullptr)
                // A sample that left in chunks is logged with its last: the whole sample's size.
                row.payload_bytes =
                    record.sample->chunk ? record.sample->chunk->total_bytes : record.sample->payload.size();
            const std::size_t footprint = sizeof(Row) + row.topic.size() + row.type_name.size();
            enqueue(std::move(row), footprint);
        } catch (const std::exception& e) {
            fail_rows(1, e.what());
        }
    }

    void append_rate(const RateRecord& record) noexcept {
        try {
            Row row;
            row.kind = Row::Kind::rate;
            row.logged_ns = base::to_ns(record.at);
            row.sensed_bps = record.sensed_bps;
            row.budget_bps = record.budget_bps;
            enqueue(std::move(row), sizeof(Row));
        } catch (const std::exception& e) {
            fail_rows(1, e.what());
        }
    }

    void flush() {
        std::unique_lock<std::mutex> lock(mutex_);
        const std::uint64_t target = appended_;
        flush_requested_ = true;
        wake_writer_.notify_one();
        done_changed_.wait(lock, [&] { return done_ >= target; });
    }

    std::uint64_t rows_written() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return rows_written_;
    }
    std::uint64_t write_errors() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return write_errors_;
    }
    std::uint64_t pruned_rows() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return pruned_rows_;
    }
    const std::string& path() const { return path_; }

  private:
    static Row common_row(std::string_view topic, std::string_view type_name, const core::Sample* sample,
                          base::WallTime arrival, base::WallTime deadline, base::WallTime logged_at) {
        Row row;
        row.topic.assign(topic.data(), topic.size());
        row.type_name.assign(type_name.data(), type_name.size());
        if (sample != nullptr) {
            if (sample->key.valid)
                row.key = sample->key;
            row.source_time_ns = base::to_ns(sample->source_time);
        }
        row.arrival_ns = base::to_ns(arrival);
        row.deadline_ns = base::to_ns(deadline);
        row.logged_ns = base::to_ns(logged_at);
        return row;
    }

    /// Hands the row to the writer, or refuses it (counted) when `charge_bytes` more would overfill the buffer.
    void enqueue(Row&& row, std::size_t charge_bytes) {
        std::unique_lock<std::mutex> lock(mutex_);
        if (buffered_bytes_ + charge_bytes > MAX_BUFFERED_BYTES) {
            lock.unlock();
            fail_rows(1, "buffer full: the disk is not keeping up");
            return;
        }
        pending_.push_back(std::move(row));
        ++appended_;
        buffered_bytes_ += charge_bytes;
        if (pending_.size() == 1)
            first_pending_at_ = std::chrono::steady_clock::now();
        // The writer waits for the first row, then for a full batch or the batch delay; wake it only then.
        const bool wake = pending_.size() == 1 || pending_.size() == BATCH_ROWS;
        lock.unlock();
        if (wake)
            wake_writer_.notify_one();
    }

    [[noreturn]] void fail_open(const std::string& what) const {
        std::string message = "on-robot log " + path_ + ": " + what;
        if (db_ != nullptr)
            message += ": " + std::string(sqlite3_errmsg(db_.get()));
        throw base::ConfigError(message);
    }

    void exec_or_fail(const char* sql, const char* what) {
        if (sqlite3_exec(db_.get(), sql, nullptr, nullptr, nullptr) != SQLITE_OK)
            fail_open(what);
    }

    /// Opens or creates the file, turns WAL on and checks or creates the schema. Throws base::ConfigError.
    void open() {
        if (path_.empty())
            throw base::ConfigError("on-robot log: the file name is empty");
        sqlite3* raw = nullptr;
        const int rc = sqlite3_open_v2(path_.c_str(), &raw, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr);
        db_.reset(raw);  // sqlite3_open_v2 hands out a handle even on failure, to carry the message
        if (rc != SQLITE_OK)
            fail_open("cannot open");
        sqlite3_extended_result_codes(db_.get(), 1);
        sqlite3_busy_timeout(db_.get(), BUSY_TIMEOUT_MS);

        // SQLite opens lazily: the first statement is where an unwritable or foreign file shows.
        sqlite3_stmt* raw_stmt = nullptr;
        if (sqlite3_prepare_v2(db_.get(), "PRAGMA journal_mode=WAL;", -1, &raw_stmt, nullptr) != SQLITE_OK)
            fail_open("cannot open");
        StmtPtr wal(raw_stmt);
        if (sqlite3_step(wal.get()) != SQLITE_ROW)
            fail_open("cannot switch to WAL mode");
        const auto* mode = reinterpret_cast<const char*>(sqlite3_column_text(wal.get(), 0));
        if (mode == nullptr || std::string(mode) != "wal")
            throw base::ConfigError("on-robot log " + path_ + ": the file system does not support WAL mode (got " +
                                    (mode ? mode : "nothing") + ")");
        wal.reset();

        // In WAL mode, NORMAL loses at most the last commits on power loss and never corrupts the file.
        exec_or_fail("PRAGMA synchronous=NORMAL;", "cannot set synchronous mode");
        exec_or_fail("BEGIN IMMEDIATE;", "cannot create the schema");
        exec_or_fail(SCHEMA_SQL, "cannot create the schema");
        exec_or_fail(("INSERT OR IGNORE INTO meta (key, value) VALUES ('schema_version', '" +
                      std::to_string(SCHEMA_VERSION) + "');")
                         .c_str(),
                     "cannot create the schema");
        exec_or_fail("COMMIT;", "cannot create the schema");
        check_schema_version();

        if (sqlite3_prepare_v3(db_.get(), INSERT_SQL, -1, SQLITE_PREPARE_PERSISTENT, &raw_stmt, nullptr) != SQLITE_OK)
            fail_open("cannot prepare the insert statement");
        insert_.reset(raw_stmt);
        if (sqlite3_prepare_v3(db_.get(), INSERT_FORWARDED_SQL, -1, SQLITE_PREPARE_PERSISTENT, &raw_stmt, nullptr) !=
            SQLITE_OK)
            fail_open("cannot prepare the insert statement");
        insert_forwarded_.reset(raw_stmt);
        if (sqlite3_prepare_v3(db_.get(), INSERT_RATE_SQL, -1, SQLITE_PREPARE_PERSISTENT, &raw_stmt, nullptr) !=
            SQLITE_OK)
            fail_open("cannot prepare the insert statement");
        insert_rate_.reset(raw_stmt);
    }

    void check_schema_version() {
        sqlite3_stmt* raw = nullptr;
        if (sqlite3_prepare_v2(db_.get(), "SELECT value FROM meta WHERE key = 'schema_version';", -1, &raw, nullptr) !=
            SQLITE_OK)
            fail_open("cannot read the schema version");
        StmtPtr stmt(raw);
        if (sqlite3_step(stmt.get()) != SQLITE_ROW)
            fail_open("cannot read the schema version");
        const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt.get(), 0));
        const std::string version = text ? text : "";
        if (version != std::to_string(SCHEMA_VERSION))
            throw base::ConfigError("on-robot log " + path_ + ": schema version " + version + ", this gateway writes " +
                                    std::to_string(SCHEMA_VERSION));
    }

    /// The writer thread: commits the buffer in batches until stopped, then commits what is left.
    void run() {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            if (pending_.empty()) {
                if (stopping_)
                    break;
                if (flush_requested_) {
                    flush_requested_ = false;  // everything appended before the flush is already done
                    continue;
                }
                wake_writer_.wait(lock, [&] { return stopping_ || flush_requested_ || !pending_.empty(); });
                continue;
            }
            wake_writer_.wait_until(lock, first_pending_at_ + BATCH_DELAY,
                                    [&] { return stopping_ || flush_requested_ || pending_.size() >= BATCH_ROWS; });
            std::vector<Row> batch;
            batch.swap(pending_);
            buffered_bytes_ = 0;
            flush_requested_ = false;
            lock.unlock();
            const std::size_t written = write_batch(batch);
            const std::uint64_t pruned = max_bytes_ > 0 ? keep_under_cap() : 0;
            lock.lock();
            rows_written_ += written;
            pruned_rows_ += pruned;
            done_ += batch.size();
            done_changed_.notify_all();
        }
    }

    /// Writes the rows in one transaction; returns how many were committed. Called on the writer thread only.
    std::size_t write_batch(const std::vector<Row>& batch) {
        sqlite3* db = db_.get();
        if (sqlite3_exec(db, "BEGIN;", nullptr, nullptr, nullptr) != SQLITE_OK) {
            fail_rows(batch.size(), sqlite3_errmsg(db));
            return 0;
        }
        std::size_t inserted = 0;
        for (const Row& row : batch) {
            const bool ok = row.kind == Row::Kind::rate        ? insert_rate(row)
                            : row.kind == Row::Kind::forwarded ? insert_forwarded(row)
                                                               : insert(row);
            if (!ok)
                fail_rows(1, sqlite3_errmsg(db));
            else if (row.kind != Row::Kind::rate)  // rows_written counts samples
                ++inserted;
        }
        if (sqlite3_exec(db, "COMMIT;", nullptr, nullptr, nullptr) != SQLITE_OK) {
            fail_rows(inserted, sqlite3_errmsg(db));
            sqlite3_exec(db, "ROLLBACK;", nullptr, nullptr, nullptr);
            return 0;
        }
        return inserted;
    }

    bool insert(const Row& row) {
        sqlite3_stmt* stmt = insert_.get();
        sqlite3_reset(stmt);
        // SQLITE_STATIC: the row outlives the step.
        sqlite3_bind_text(stmt, 1, row.topic.data(), static_cast<int>(row.topic.size()), SQLITE_STATIC);
        sqlite3_bind_text(stmt, 2, row.type_name.data(), static_cast<int>(row.type_name.size()), SQLITE_STATIC);
        // A zero-length blob, not NULL, for an empty payload: the column is NOT NULL.
        sqlite3_bind_blob(stmt, 3, row.payload.empty() ? "" : static_cast<const void*>(row.payload.data()),
                          static_cast<int>(row.payload.size()), SQLITE_STATIC);
        bind_key(stmt, 4, row);
        sqlite3_bind_int64(stmt, 5, row.source_time_ns);
        sqlite3_bind_int64(stmt, 6, row.arrival_ns);
        sqlite3_bind_int64(stmt, 7, row.deadline_ns);
        sqlite3_bind_int64(stmt, 8, row.logged_ns);
        const std::string_view reason = core::to_string(row.reason);
        sqlite3_bind_text(stmt, 9, reason.data(), static_cast<int>(reason.size()), SQLITE_STATIC);
        return step(stmt);
    }

    bool insert_forwarded(const Row& row) {
        sqlite3_stmt* stmt = insert_forwarded_.get();
        sqlite3_reset(stmt);
        sqlite3_bind_text(stmt, 1, row.topic.data(), static_cast<int>(row.topic.size()), SQLITE_STATIC);
        sqlite3_bind_text(stmt, 2, row.type_name.data(), static_cast<int>(row.type_name.size()), SQLITE_STATIC);
        bind_key(stmt, 3, row);
        sqlite3_bind_int64(stmt, 4, row.source_time_ns);
        sqlite3_bind_int64(stmt, 5, row.arrival_ns);
        sqlite3_bind_int64(stmt, 6, row.deadline_ns);
        sqlite3_bind_int64(stmt, 7, row.logged_ns);
        sqlite3_bind_int64(stmt, 8, static_cast<sqlite3_int64>(row.payload_bytes));
        return step(stmt);
    }

    static void bind_key(sqlite3_stmt* stmt, int index, const Row& row) {
        if (row.key)
            sqlite3_bind_blob(stmt, index, row.key->bytes.data(), static_cast<int>(row.key->bytes.size()),
                              SQLITE_STATIC);
        else
            sqlite3_bind_null(stmt, index);
    }

    bool insert_rate(const Row& row) {
        sqlite3_stmt* stmt = insert_rate_.get();
        sqlite3_reset(stmt);
        sqlite3_bind_int64(stmt, 1, row.logged_ns);
        sqlite3_bind_double(stmt, 2, row.sensed_bps);
        sqlite3_bind_double(stmt, 3, row.budget_bps);
        return step(stmt);
    }

    static bool step(sqlite3_stmt* stmt) {
        const bool ok = sqlite3_step(stmt) == SQLITE_DONE;
        sqlite3_reset(stmt);
        sqlite3_clear_bindings(stmt);
        return ok;
    }

    /// The bytes the file's rows take: its pages less those free for reuse.
    std::uint64_t live_bytes() {
        sqlite3_stmt* raw = nullptr;
        if (sqlite3_prepare_v2(db_.get(),
                               "SELECT MAX(0, page_count - freelist_count) * page_size "
                               "FROM pragma_page_count(), pragma_freelist_count(), pragma_page_size();",
                               -1, &raw, nullptr) != SQLITE_OK)
            return 0;
        StmtPtr stmt(raw);
        return sqlite3_step(stmt.get()) == SQLITE_ROW ? static_cast<std::uint64_t>(sqlite3_column_int64(stmt.get(), 0))
                                                      : 0;
    }

    /// Deletes the oldest rows (by insertion) of `table`, PRUNE_ROWS at a time; returns how many.
    std::uint64_t delete_oldest(const char* table) {
        const std::string sql = std::string("DELETE FROM ") + table + " WHERE rowid IN (SELECT rowid FROM " + table +
                                " ORDER BY rowid LIMIT " + std::to_string(PRUNE_ROWS) + ");";
        if (sqlite3_exec(db_.get(), sql.c_str(), nullptr, nullptr, nullptr) != SQLITE_OK)
            return 0;
        return static_cast<std::uint64_t>(sqlite3_changes(db_.get()));
    }

    /// Past the cap, the oldest rows go until the rows take 90 % of it: freed pages are reused, so the file
    /// stops growing. Returns the rows deleted. Writer thread only.
    std::uint64_t keep_under_cap() {
        if (live_bytes() <= max_bytes_)
            return 0;
        const std::uint64_t target = max_bytes_ / 10 * 9;
        std::uint64_t forwarded = 0;
        std::uint64_t dropped = 0;
        while (live_bytes() > target) {
            if (const std::uint64_t n = delete_oldest("forwarded_samples"); n > 0) {
                forwarded += n;
            } else if (const std::uint64_t m = delete_oldest("dropped_samples"); m > 0) {
                dropped += m;
            } else {
                break;  // the link rates and the schema are all that is left
            }
        }
        for (const auto& [key, n] : {std::pair<const char*, std::uint64_t>{"pruned_forwarded_rows", forwarded},
                                     std::pair<const char*, std::uint64_t>{"pruned_dropped_rows", dropped}}) {
            const std::string sql = std::string("INSERT INTO meta (key, value) VALUES ('") + key + "', '" +
                                    std::to_string(n) +
                                    "') ON CONFLICT(key) DO UPDATE SET value = CAST(CAST(value AS INTEGER) + "
                                    "CAST(excluded.value AS INTEGER) AS TEXT);";
            sqlite3_exec(db_.get(), sql.c_str(), nullptr, nullptr, nullptr);
        }
        if (!cap_reported_) {
            cap_reported_ = true;
            std::fprintf(stderr,
                         "on-robot log %s: at its cap of %llu MiB: the oldest rows make room, sent ones first (counts "
                         "in its meta table)\n",
                         path_.c_str(), static_cast<unsigned long long>(max_bytes_ >> 20));
        }
        return forwarded + dropped;
    }

    /// Counts `n` rows as lost; the first failure is reported on stderr, the rest only counted.
    void fail_rows(std::size_t n, const char* why) noexcept {
        if (n == 0)
            return;
        bool first = false;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            first = write_errors_ == 0;
            write_errors_ += n;
        }
        if (first)
            std::fprintf(stderr, "on-robot log %s: write failed: %s (further failures are only counted)\n",
                         path_.c_str(), why);
    }

    const std::string path_;
    const std::uint64_t max_bytes_;
    bool cap_reported_ = false;  ///< writer thread only
    DbPtr db_;
    StmtPtr insert_;
    StmtPtr insert_forwarded_;
    StmtPtr insert_rate_;

    mutable std::mutex mutex_;
    std::condition_variable wake_writer_;
    std::condition_variable done_changed_;
    std::vector<Row> pending_;
    std::size_t buffered_bytes_ = 0;
    std::chrono::steady_clock::time_point first_pending_at_{};
    std::uint64_t appended_ = 0;  ///< rows that reached the buffer
    std::uint64_t done_ = 0;      ///< rows the writer has finished with, written or failed
    std::uint64_t rows_written_ = 0;
    std::uint64_t write_errors_ = 0;
    std::uint64_t pruned_rows_ = 0;
    bool flush_requested_ = false;
    bool stopping_ = false;
    std::thread writer_;
};

RobotLog::RobotLog(const std::string& path, std::uint64_t max_bytes) : impl_(std::make_unique<Impl>(path, max_bytes)) {}

RobotLog::~RobotLog() = default;

void RobotLog::append(const LogRecord& record) {
    impl_->append(record);
}

void RobotLog::append_forwarded(const ForwardRecord& record) {
    impl_->append_forwarded(record);
}

void RobotLog::append_rate(const RateRecord& record) {
    impl_->append_rate(record);
}

void RobotLog::flush() {
    impl_->flush();
}

std::uint64_t RobotLog::rows_written() const {
    return impl_->rows_written();
}

std::uint64_t RobotLog::pruned_rows() const {
    return impl_->pruned_rows();
}

std::uint64_t RobotLog::write_errors() const {
    return impl_->write_errors();
}

const std::string& RobotLog::path() const {
    return impl_->path();
}

}  // namespace tgw::log
