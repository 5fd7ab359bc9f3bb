#include "gateway/log/robot_log.hpp"

#include <sqlite3.h>

#include <array>
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
#include "base/sqlite_handles.hpp"
#include "gateway/log/backfill_reader.hpp"
#include "gateway/log/interned_names.hpp"
#include "gateway/log/log_schema.hpp"

namespace tgw::log {

namespace {

/// A batch is committed when it holds this many rows, or when its oldest row has waited BATCH_DELAY.
constexpr std::size_t BATCH_ROWS = 1000;
constexpr auto BATCH_DELAY = std::chrono::milliseconds(50);
/// The batch's vector is kept for the next up to this many rows; one that a stalled disk made larger goes.
constexpr std::size_t MAX_SPARE_ROWS = 4 * BATCH_ROWS;
/// Past this much buffered payload (the disk stalled, or is far slower than the drops), further rows are
/// refused and counted as write errors rather than letting the gateway run out of memory. A forwarded row has
/// no payload and counts for its own size instead.
constexpr std::size_t MAX_BUFFERED_BYTES = std::size_t{256} << 20;
/// How long a write waits for a reader of the file (sqlite3, tm-basecamp) to let go of a lock.
constexpr int BUSY_TIMEOUT_MS = 2000;
/// Rows deleted per statement while the file is over its cap: few, so that large rows do not take the file far
/// below the cap.
constexpr int PRUNE_ROWS = 16;

/// A record copied out of the caller's sample, owned by the buffer: a dropped sample, a forwarded one, a rate, or
/// backfill's mark of dropped rows.
struct Row {
    enum class Kind { dropped, forwarded, rate, sent, acknowledged };
    Kind kind = Kind::dropped;
    std::string_view topic;             ///< the log's copy (InternedNames), once the row is in the buffer
    std::string_view type_name;         ///< the same
    std::vector<std::uint8_t> payload;  ///< dropped rows only
    std::size_t payload_bytes = 0;      ///< forwarded rows only
    std::optional<core::InstanceKey> key;
    std::int64_t source_time_ns = 0;
    std::int64_t arrival_ns = 0;
    std::int64_t deadline_ns = 0;
    std::int64_t logged_ns = 0;  ///< dropped: when logged; forwarded: when written to the WAN; rate, marks: its time
    core::DropReason reason = core::DropReason::expired;
    core::SampleKind sample_kind = core::SampleKind::data;  ///< dropped rows only
    double sensed_bps = 0, budget_bps = 0;                  ///< rate rows only
    std::int64_t first_row_id = 0, last_row_id = 0;         ///< marks only: the dropped rows marked (sent: first only)
};

/// What one batch's transaction committed.
struct BatchResult {
    std::size_t samples = 0;         ///< rows of both sample tables
    std::uint64_t acknowledged = 0;  ///< dropped rows newly acknowledged
};

}  // namespace

class RobotLog::Impl {
  public:
    Impl(const std::string& path, std::uint64_t max_bytes) : path_(path), max_bytes_(max_bytes) {
        open();
        reader_ = std::make_unique<BackfillReader>(path_);
        writer_ = std::thread([this] { run(); });
    }

    ~Impl() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
        }
        wake_writer_.notify_one();
        writer_.join();  // the writer commits everything still buffered before it returns
        // The reader first: the last connection to close checkpoints the WAL into the file, and a read-only one
        // cannot.
        reader_.reset();
        insert_.reset();
        insert_forwarded_.reset();
        insert_rate_.reset();
        mark_sent_.reset();
        mark_acknowledged_.reset();
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
            if (record.payload_bytes)
                row.payload_bytes = *record.payload_bytes;
            else if (record.sample != nullptr)
                // A sample that left in chunks is logged with its last: the whole sample's size.
                row.payload_bytes =
                    record.sample->chunk ? record.sample->chunk->total_bytes : record.sample->payload.size();
            enqueue(std::move(row), sizeof(Row));
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

    void mark_sent(std::int64_t row_id, base::WallTime at) noexcept { mark(Row::Kind::sent, row_id, row_id, at); }

    void mark_acknowledged(std::int64_t first_row_id, std::int64_t last_row_id, base::WallTime at) noexcept {
        mark(Row::Kind::acknowledged, first_row_id, last_row_id, at);
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
    std::uint64_t acknowledged_rows() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return acknowledged_rows_;
    }
    const std::string& path() const { return path_; }
    /// Set once in open(), before any other thread sees the log.
    const std::string& log_id() const { return log_id_; }
    BackfillReader& reader() { return *reader_; }

  private:
    static Row common_row(std::string_view topic, std::string_view type_name, const core::Sample* sample,
                          base::WallTime arrival, base::WallTime deadline, base::WallTime logged_at) {
        Row row;
        row.topic = topic;  // the caller's until enqueue() takes the log's copy
        row.type_name = type_name;
        if (sample != nullptr) {
            if (sample->key.valid)
                row.key = sample->key;
            row.source_time_ns = base::to_ns(sample->source_time);
            row.sample_kind = sample->kind;
        }
        row.arrival_ns = base::to_ns(arrival);
        row.deadline_ns = base::to_ns(deadline);
        row.logged_ns = base::to_ns(logged_at);
        return row;
    }

    void mark(Row::Kind kind, std::int64_t first_row_id, std::int64_t last_row_id, base::WallTime at) noexcept {
        try {
            Row row;
            row.kind = kind;
            row.first_row_id = first_row_id;
            row.last_row_id = last_row_id;
            row.logged_ns = base::to_ns(at);
            enqueue(std::move(row), sizeof(Row));
        } catch (const std::exception& e) {
            fail_rows(1, e.what());
        }
    }

    /// Hands the row to the writer, or refuses it (counted) when `charge_bytes` more would overfill the buffer.
    void enqueue(Row&& row, std::size_t charge_bytes) {
        std::unique_lock<std::mutex> lock(mutex_);
        if (buffered_bytes_ + charge_bytes > MAX_BUFFERED_BYTES) {
            lock.unlock();
            fail_rows(1, "buffer full: the disk is not keeping up");
            return;
        }
        if (row.kind == Row::Kind::dropped || row.kind == Row::Kind::forwarded) {
            row.topic = names_.intern(row.topic);
            row.type_name = names_.intern(row.type_name);
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
        base::StmtPtr wal(raw_stmt);
        if (sqlite3_step(wal.get()) != SQLITE_ROW)
            fail_open("cannot switch to WAL mode");
        const auto* mode = reinterpret_cast<const char*>(sqlite3_column_text(wal.get(), 0));
        if (mode == nullptr || std::string(mode) != "wal")
            throw base::ConfigError("on-robot log " + path_ + ": the file system does not support WAL mode (got " +
                                    (mode ? mode : "nothing") + ")");
        wal.reset();

        // In WAL mode, NORMAL loses at most the last commits on power loss and never corrupts the file.
        exec_or_fail("PRAGMA synchronous=NORMAL;", "cannot set synchronous mode");
        // One transaction: a file is migrated whole or not at all. Thrown out of, it is rolled back as the
        // connection closes.
        exec_or_fail("BEGIN IMMEDIATE;", "cannot create the schema");
        exec_or_fail(SCHEMA_SQL, "cannot create the schema");
        exec_or_fail(("INSERT OR IGNORE INTO meta (key, value) VALUES ('schema_version', '" +
                      std::to_string(SCHEMA_VERSION) + "');")
                         .c_str(),
                     "cannot create the schema");
        check_schema_version();  // before migrating: a file of another version is left as it was
        add_backfill_columns();
        exec_or_fail(BACKFILL_INDEX_SQL, "cannot create the backfill indexes");
        exec_or_fail(LOG_ID_SQL, "cannot make the log id");
        log_id_ = meta_value("log_id");
        const std::optional<std::int64_t> max_dropped_id = query_int64(MAX_DROPPED_ID_SQL);
        if (!max_dropped_id)
            fail_open("cannot read the largest id of dropped_samples");
        next_dropped_id_ = *max_dropped_id + 1;
        exec_or_fail("COMMIT;", "cannot create the schema");

        insert_ = prepare_or_fail(INSERT_SQL);
        insert_forwarded_ = prepare_or_fail(INSERT_FORWARDED_SQL);
        insert_rate_ = prepare_or_fail(INSERT_RATE_SQL);
        mark_sent_ = prepare_or_fail(MARK_SENT_SQL);
        mark_acknowledged_ = prepare_or_fail(MARK_ACKNOWLEDGED_SQL);
    }

    base::StmtPtr prepare_or_fail(const char* sql) {
        base::StmtPtr stmt = base::prepare_persistent(db_.get(), sql);
        if (stmt == nullptr)
            fail_open("cannot prepare a statement");
        return stmt;
    }

    /// The value of `key` in the meta table. Throws base::ConfigError when there is none.
    std::string meta_value(const char* key) {
        sqlite3_stmt* raw = nullptr;
        if (sqlite3_prepare_v2(db_.get(), "SELECT value FROM meta WHERE key = ?1;", -1, &raw, nullptr) != SQLITE_OK)
            fail_open(std::string("cannot read ") + key);
        base::StmtPtr stmt(raw);
        sqlite3_bind_text(stmt.get(), 1, key, -1, SQLITE_STATIC);
        if (sqlite3_step(stmt.get()) != SQLITE_ROW)
            fail_open(std::string("cannot read ") + key);
        const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt.get(), 0));
        return text ? text : "";
    }

    void check_schema_version() {
        const std::string version = meta_value("schema_version");
        if (version != std::to_string(SCHEMA_VERSION))
            throw base::ConfigError("on-robot log " + path_ + ": schema version " + version + ", this gateway writes " +
                                    std::to_string(SCHEMA_VERSION));
    }

    /// Adds the BACKFILL_COLUMNS that dropped_samples lacks. In open()'s transaction.
    void add_backfill_columns() {
        sqlite3_stmt* raw = nullptr;
        if (sqlite3_prepare_v2(db_.get(), "SELECT COUNT(*) FROM pragma_table_info('dropped_samples') WHERE name = ?1;",
                               -1, &raw, nullptr) != SQLITE_OK)
            fail_open("cannot read the columns of dropped_samples");
        base::StmtPtr has_column(raw);
        for (const auto& [name, definition] : BACKFILL_COLUMNS) {
            sqlite3_reset(has_column.get());
            sqlite3_bind_text(has_column.get(), 1, name, -1, SQLITE_STATIC);
            if (sqlite3_step(has_column.get()) != SQLITE_ROW)
                fail_open("cannot read the columns of dropped_samples");
            if (sqlite3_column_int64(has_column.get(), 0) > 0)
                continue;
            // ALTER TABLE ADD COLUMN only rewrites the schema: the rows read the default until written.
            exec_or_fail(
                (std::string("ALTER TABLE dropped_samples ADD COLUMN ") + name + " " + definition + ";").c_str(),
                "cannot add the backfill columns to dropped_samples");
        }
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
            // The buffer goes on with the last batch's vector: appending a row does not grow it again.
            pending_.swap(spare_rows_);
            buffered_bytes_ = 0;
            flush_requested_ = false;
            lock.unlock();
            const BatchResult written = write_batch(batch);
            const std::uint64_t pruned = max_bytes_ > 0 ? keep_under_cap() : 0;
            lock.lock();
            rows_written_ += written.samples;
            acknowledged_rows_ += written.acknowledged;
            pruned_rows_ += pruned;
            done_ += batch.size();
            if (batch.capacity() <= MAX_SPARE_ROWS) {
                batch.clear();
                spare_rows_.swap(batch);
            }
            done_changed_.notify_all();
        }
    }

    /// Writes the rows and marks in one transaction; returns what it committed. Called on the writer thread only.
    BatchResult write_batch(const std::vector<Row>& batch) {
        sqlite3* db = db_.get();
        if (sqlite3_exec(db, "BEGIN;", nullptr, nullptr, nullptr) != SQLITE_OK) {
            fail_rows(batch.size(), sqlite3_errmsg(db));
            return {};
        }
        BatchResult result;
        for (const Row& row : batch) {
            bool ok = false;
            switch (row.kind) {
                case Row::Kind::dropped:
                    ok = insert(row);
                    result.samples += ok ? 1 : 0;
                    break;
                case Row::Kind::forwarded:
                    ok = insert_forwarded(row);
                    result.samples += ok ? 1 : 0;
                    break;
                case Row::Kind::rate:
                    ok = insert_rate(row);
                    break;
                case Row::Kind::sent:
                    ok = update(mark_sent_.get(), row);
                    break;
                case Row::Kind::acknowledged:
                    ok = update(mark_acknowledged_.get(), row);
                    result.acknowledged += ok ? static_cast<std::uint64_t>(sqlite3_changes(db)) : 0;
                    break;
            }
            if (!ok)
                fail_rows(1, sqlite3_errmsg(db));
        }
        if (sqlite3_exec(db, "COMMIT;", nullptr, nullptr, nullptr) != SQLITE_OK) {
            fail_rows(result.samples, sqlite3_errmsg(db));
            sqlite3_exec(db, "ROLLBACK;", nullptr, nullptr, nullptr);
            return {};
        }
        return result;
    }

    /// Steps a mark's UPDATE: ?1 the first row, ?2 the time (sent) or the last row, ?3 the time (acknowledged).
    static bool update(sqlite3_stmt* stmt, const Row& row) {
        sqlite3_reset(stmt);
        sqlite3_bind_int64(stmt, 1, row.first_row_id);
        if (row.kind == Row::Kind::sent) {
            sqlite3_bind_int64(stmt, 2, row.logged_ns);
        } else {
            sqlite3_bind_int64(stmt, 2, row.last_row_id);
            sqlite3_bind_int64(stmt, 3, row.logged_ns);
        }
        return step(stmt);
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
        sqlite3_bind_int64(stmt, 10, next_dropped_id_);
        const std::string_view kind = core::to_string(row.sample_kind);
        sqlite3_bind_text(stmt, 11, kind.data(), static_cast<int>(kind.size()), SQLITE_STATIC);
        if (!step(stmt))
            return false;
        ++next_dropped_id_;
        return true;
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

    /// The first column of the first row `sql` gives; nullopt when it gives none or fails.
    std::optional<std::int64_t> query_int64(const char* sql) {
        sqlite3_stmt* raw = nullptr;
        if (sqlite3_prepare_v2(db_.get(), sql, -1, &raw, nullptr) != SQLITE_OK)
            return std::nullopt;
        base::StmtPtr stmt(raw);
        if (sqlite3_step(stmt.get()) != SQLITE_ROW)
            return std::nullopt;
        return sqlite3_column_int64(stmt.get(), 0);
    }

    /// The bytes the file's rows take: its pages less those free for reuse.
    std::uint64_t live_bytes() {
        const std::optional<std::int64_t> bytes = query_int64(
            "SELECT MAX(0, page_count - freelist_count) * page_size "
            "FROM pragma_page_count(), pragma_freelist_count(), pragma_page_size();");
        return bytes ? static_cast<std::uint64_t>(*bytes) : 0;
    }

    /// Deletes the oldest rows (by insertion) of the stage's table that meet its condition, PRUNE_ROWS at a time;
    /// returns how many.
    std::uint64_t delete_oldest(const PruneStage& prune) {
        const std::string sql = std::string("DELETE FROM ") + prune.table + " WHERE id IN (SELECT id FROM " +
                                prune.table + " WHERE " + prune.condition + " ORDER BY id LIMIT " +
                                std::to_string(PRUNE_ROWS) + ");";
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
        // Kept before any row goes: were the row of the largest id pruned, SQLite would give that id again.
        const std::string keep_max_id = "INSERT INTO meta (key, value) VALUES ('max_dropped_id', '" +
                                        std::to_string(next_dropped_id_ - 1) +
                                        "') ON CONFLICT(key) DO UPDATE SET value = excluded.value;";
        if (sqlite3_exec(db_.get(), keep_max_id.c_str(), nullptr, nullptr, nullptr) != SQLITE_OK)
            return 0;  // better over the cap than an id that names two rows
        std::array<std::uint64_t, PRUNE_ORDER.size()> pruned{};
        while (live_bytes() > target) {
            std::uint64_t n = 0;
            for (std::size_t stage = 0; stage < PRUNE_ORDER.size() && n == 0; ++stage) {
                n = delete_oldest(PRUNE_ORDER[stage]);
                pruned[stage] += n;
            }
            if (n == 0)
                break;  // the link rates and the schema are all that is left
        }
        std::uint64_t total = 0;
        for (std::size_t stage = 0; stage < PRUNE_ORDER.size(); ++stage) {
            total += pruned[stage];
            const std::string sql = std::string("INSERT INTO meta (key, value) VALUES ('") +
                                    PRUNE_ORDER[stage].meta_key + "', '" + std::to_string(pruned[stage]) +
                                    "') ON CONFLICT(key) DO UPDATE SET value = CAST(CAST(value AS INTEGER) + "
                                    "CAST(excluded.value AS INTEGER) AS TEXT);";
            sqlite3_exec(db_.get(), sql.c_str(), nullptr, nullptr, nullptr);
        }
        if (!cap_reported_) {
            cap_reported_ = true;
            std::fprintf(stderr,
                         "on-robot log %s: at its cap of %llu MiB: the oldest rows make room, those the base camp "
                         "has and sent ones first (counts in its meta table)\n",
                         path_.c_str(), static_cast<unsigned long long>(max_bytes_ >> 20));
        }
        return total;
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
    /// The id of the next dropped row; writer thread only. A row's id names it for ever (with log_id_, at the base
    /// camp too), so it is never given twice, even once its row is pruned: SQLite would give the largest id left
    /// plus one, and pruning the acknowledged rows first can take the newest.
    std::int64_t next_dropped_id_ = 1;
    base::DbPtr db_;
    base::StmtPtr insert_;
    base::StmtPtr insert_forwarded_;
    base::StmtPtr insert_rate_;
    base::StmtPtr mark_sent_;
    base::StmtPtr mark_acknowledged_;
    std::string log_id_;
    std::unique_ptr<BackfillReader> reader_;

    mutable std::mutex mutex_;
    std::condition_variable wake_writer_;
    std::condition_variable done_changed_;
    std::vector<Row> pending_;
    std::vector<Row> spare_rows_;  ///< the vector of the batch last written, emptied, to be pending_ next
    InternedNames names_;          ///< the rows' names; the writer reads them without the lock, which is safe as
                                   ///< a kept name never moves
    std::size_t buffered_bytes_ = 0;
    std::chrono::steady_clock::time_point first_pending_at_{};
    std::uint64_t appended_ = 0;  ///< rows that reached the buffer
    std::uint64_t done_ = 0;      ///< rows the writer has finished with, written or failed
    std::uint64_t rows_written_ = 0;
    std::uint64_t write_errors_ = 0;
    std::uint64_t pruned_rows_ = 0;
    std::uint64_t acknowledged_rows_ = 0;
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

void RobotLog::mark_sent(std::int64_t row_id, base::WallTime at) {
    impl_->mark_sent(row_id, at);
}

void RobotLog::mark_acknowledged(std::int64_t first_row_id, std::int64_t last_row_id, base::WallTime at) {
    impl_->mark_acknowledged(first_row_id, last_row_id, at);
}

void RobotLog::flush() {
    impl_->flush();
}

std::vector<BackfillCandidate> RobotLog::unacknowledged(std::int64_t after_row_id, std::size_t max_rows) {
    return impl_->reader().unacknowledged(after_row_id, max_rows);
}

std::optional<StoredSample> RobotLog::read_dropped(std::int64_t row_id) {
    return impl_->reader().read_dropped(row_id);
}

std::string RobotLog::log_id() const {
    return impl_->log_id();
}

std::uint64_t RobotLog::rows_written() const {
    return impl_->rows_written();
}

std::uint64_t RobotLog::pruned_rows() const {
    return impl_->pruned_rows();
}

std::uint64_t RobotLog::acknowledged_rows() const {
    return impl_->acknowledged_rows();
}

std::uint64_t RobotLog::write_errors() const {
    return impl_->write_errors();
}

const std::string& RobotLog::path() const {
    return impl_->path();
}

}  // namespace tgw::log
