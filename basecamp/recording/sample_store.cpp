#include "basecamp/recording/sample_store.hpp"

#include <sqlite3.h>

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>

#include "base/config_error.hpp"
#include "base/sqlite_handles.hpp"

namespace tgw::basecamp {

namespace {

// synchronous=FULL: each commit (one per commit period) is on disk before the backfilled rows it holds are
// acknowledged, since the robot frees what the camp acknowledged; NORMAL would keep it across a crash of the
// program, not of the machine.
constexpr const char* SCHEMA = R"sql(
PRAGMA journal_mode=WAL;
PRAGMA synchronous=FULL;
CREATE TABLE IF NOT EXISTS topics(
    topic TEXT PRIMARY KEY,
    type_name TEXT NOT NULL,
    lifespan_ns INTEGER,
    keyed INTEGER NOT NULL,
    reliable INTEGER NOT NULL,
    discovered_ns INTEGER NOT NULL);
CREATE TABLE IF NOT EXISTS samples(
    id INTEGER PRIMARY KEY,
    topic TEXT NOT NULL,
    type_name TEXT NOT NULL,
    payload BLOB NOT NULL,
    source_ns INTEGER NOT NULL,
    receive_ns INTEGER NOT NULL,
    lifespan_ns INTEGER,
    instance BLOB);
CREATE TABLE IF NOT EXISTS announced_types(
    type_name TEXT PRIMARY KEY,
    idl TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS channel(
    time_ns INTEGER NOT NULL,
    channel_bps REAL NOT NULL,
    newcomer_bps REAL NOT NULL,
    verdict TEXT,
    delivered_bps REAL,
    queueing_ns INTEGER);
CREATE TABLE IF NOT EXISTS grants(
    time_ns INTEGER NOT NULL,
    gateway TEXT NOT NULL,
    robot TEXT,
    rate_bps REAL NOT NULL);
)sql";

/// The columns of samples that backfill added. The constructor adds those a file lacks with ALTER TABLE, to a new
/// file too, so that a new recording and an older one end up with one layout.
constexpr std::array<std::pair<const char*, const char*>, 4> BACKFILL_COLUMNS{{
    {"backfilled", "INTEGER NOT NULL DEFAULT 0"},
    {"log_id", "TEXT"},  // the on-robot log's id; NULL for a live sample
    {"row_id", "INTEGER"},
    {"drop_reason", "TEXT"},
}};

// Partial: live samples, the bulk of the table, never collide (their log_id is NULL) and need not pay for the index.
constexpr const char* BACKFILL_INDEX_SQL =
    "CREATE UNIQUE INDEX IF NOT EXISTS samples_backfill_row ON samples(log_id, row_id) WHERE log_id IS NOT NULL;";

// DO NOTHING only on that index, not OR IGNORE: a row that failed another constraint must count as an error, not
// as a duplicate the robot is told is stored.
constexpr const char* INSERT_BACKFILL_SQL =
    "INSERT INTO samples(topic, type_name, payload, source_ns, receive_ns, lifespan_ns, instance, backfilled, log_id, "
    "row_id, drop_reason) VALUES(?,?,?,?,?,?,?,1,?,?,?) "
    "ON CONFLICT(log_id, row_id) WHERE log_id IS NOT NULL DO NOTHING";

/// An INTEGER or a REAL column's value, NULL when absent.
template <typename Number>
void bind_optional(sqlite3_stmt* stmt, int index, const std::optional<Number>& value) {
    if (!value)
        sqlite3_bind_null(stmt, index);
    else if constexpr (std::is_floating_point_v<Number>)
        sqlite3_bind_double(stmt, index, *value);
    else
        sqlite3_bind_int64(stmt, index, *value);
}

void bind_text_or_null(sqlite3_stmt* stmt, int index, const std::string& text) {
    if (text.empty())
        sqlite3_bind_null(stmt, index);
    else
        sqlite3_bind_text(stmt, index, text.c_str(), -1, SQLITE_TRANSIENT);
}

void bind_blob(sqlite3_stmt* stmt, int index, const std::vector<std::uint8_t>& bytes, bool null_if_empty) {
    if (bytes.empty() && null_if_empty)
        sqlite3_bind_null(stmt, index);
    else
        sqlite3_bind_blob(stmt, index, bytes.empty() ? "" : static_cast<const void*>(bytes.data()),
                          static_cast<int>(bytes.size()), SQLITE_TRANSIENT);
}

/// The first seven columns, which a live and a backfilled sample share.
void bind_sample(sqlite3_stmt* stmt, const SampleRecord& s) {
    sqlite3_bind_text(stmt, 1, s.topic.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(stmt, 2, s.type_name.c_str(), -1, SQLITE_TRANSIENT);
    bind_blob(stmt, 3, s.payload, false);
    sqlite3_bind_int64(stmt, 4, s.source_ns);
    sqlite3_bind_int64(stmt, 5, s.receive_ns);
    bind_optional(stmt, 6, s.lifespan_ns);
    bind_blob(stmt, 7, s.instance, true);
}

}  // namespace

class SampleStore::Impl {
  public:
    Impl(const std::string& path, const std::string& flag, int commit_period_ms) : period_(commit_period_ms) {
        sqlite3* raw = nullptr;
        const int opened = sqlite3_open(path.c_str(), &raw);
        db_.reset(raw);
        if (opened != SQLITE_OK) {
            const std::string why = raw ? sqlite3_errmsg(raw) : "out of memory";
            throw base::ConfigError(flag + ": cannot open '" + path + "': " + why);
        }
        char* error = nullptr;
        if (sqlite3_exec(db_.get(), SCHEMA, nullptr, nullptr, &error) != SQLITE_OK) {
            const std::string why = error ? error : "unknown error";
            sqlite3_free(error);
            throw base::ConfigError(flag + ": cannot create tables in '" + path + "': " + why);
        }
        if (const std::string why = add_backfill_columns(); !why.empty()) {
            throw base::ConfigError(flag + ": cannot add the backfill columns to '" + path + "': " + why);
        }
        // A statement that did not prepare would crash the writer (sqlite3_clear_bindings takes no NULL).
        std::string why;
        const auto prepare = [&](const char* sql, base::StmtPtr& stmt) {
            sqlite3_stmt* raw_stmt = nullptr;
            if (sqlite3_prepare_v2(db_.get(), sql, -1, &raw_stmt, nullptr) != SQLITE_OK && why.empty())
                why = sqlite3_errmsg(db_.get());
            stmt.reset(raw_stmt);
        };
        prepare(
            "INSERT INTO samples(topic, type_name, payload, source_ns, receive_ns, lifespan_ns, instance) "
            "VALUES(?,?,?,?,?,?,?)",
            insert_sample_);
        prepare(INSERT_BACKFILL_SQL, insert_backfill_);
        prepare(
            "INSERT OR REPLACE INTO topics(topic, type_name, lifespan_ns, keyed, reliable, discovered_ns) "
            "VALUES(?,?,?,?,?,?)",
            insert_topic_);
        prepare("INSERT OR REPLACE INTO announced_types(type_name, idl) VALUES(?,?)", insert_announced_type_);
        prepare(
            "INSERT INTO channel(time_ns, channel_bps, newcomer_bps, verdict, delivered_bps, queueing_ns) "
            "VALUES(?,?,?,?,?,?)",
            insert_channel_);
        prepare("INSERT INTO grants(time_ns, gateway, robot, rate_bps) VALUES(?,?,?,?)", insert_grant_);
        if (!why.empty()) {
            throw base::ConfigError(flag + ": cannot write to '" + path + "': " + why);
        }
        writer_ = std::thread([this] { write_loop(); });
    }

    ~Impl() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
        }
        wake_.notify_all();
        writer_.join();
    }

    void add_topic(TopicRecord topic) { enqueue(topics_, std::move(topic)); }
    void add(SampleRecord sample) { enqueue(samples_, std::move(sample)); }
    void add_channel(ChannelRecord channel) { enqueue(channels_, std::move(channel)); }

    void flush() {
        std::unique_lock<std::mutex> lock(mutex_);
        const std::uint64_t target = added_;
        flush_requested_ = true;
        wake_.notify_all();
        done_.wait(lock, [&] { return committed_ >= target; });
    }

    void on_backfill_stored(StoredBackfill callback) {
        std::lock_guard<std::mutex> lock(stored_backfill_mutex_);
        stored_backfill_ = std::move(callback);
    }

    std::atomic<std::uint64_t> rows_written{0};
    std::atomic<std::uint64_t> write_errors{0};
    std::atomic<std::uint64_t> duplicate_backfill_rows{0};

  private:
    /// Adds the BACKFILL_COLUMNS that samples lacks, and their index, in one transaction. Returns why it failed, or
    /// an empty string.
    std::string add_backfill_columns() {
        std::string why;
        const auto exec = [&](const std::string& sql) {
            char* error = nullptr;
            if (why.empty() && sqlite3_exec(db_.get(), sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK)
                why = error ? error : sqlite3_errmsg(db_.get());
            sqlite3_free(error);
        };
        // IMMEDIATE: of two programs opening one old recording at once, one adds the columns, the other finds them.
        exec("BEGIN IMMEDIATE");
        if (!why.empty())
            return why;
        sqlite3_stmt* has_column = nullptr;
        sqlite3_prepare_v2(db_.get(), "SELECT 1 FROM pragma_table_info('samples') WHERE name = ?", -1, &has_column,
                           nullptr);
        for (const auto& [name, definition] : BACKFILL_COLUMNS) {
            sqlite3_reset(has_column);
            sqlite3_bind_text(has_column, 1, name, -1, SQLITE_STATIC);
            const int found = sqlite3_step(has_column);
            if (found == SQLITE_DONE)
                exec(std::string("ALTER TABLE samples ADD COLUMN ") + name + " " + definition);
            else if (found != SQLITE_ROW && why.empty())
                why = std::string("cannot read the columns of samples: ") + sqlite3_errmsg(db_.get());
        }
        sqlite3_finalize(has_column);
        exec(BACKFILL_INDEX_SQL);
        exec("COMMIT");
        if (!why.empty())
            sqlite3_exec(db_.get(), "ROLLBACK", nullptr, nullptr, nullptr);
        return why;
    }

    /// For the writer thread's next batch.
    template <typename Record>
    void enqueue(std::vector<Record>& pending, Record record) {
        std::lock_guard<std::mutex> lock(mutex_);
        pending.push_back(std::move(record));
        ++added_;
    }

    void write_loop() {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            wake_.wait_for(lock, period_, [&] { return stopping_ || flush_requested_; });
            flush_requested_ = false;
            std::vector<TopicRecord> topics;
            std::vector<SampleRecord> samples;
            std::vector<ChannelRecord> channels;
            topics.swap(topics_);
            samples.swap(samples_);
            channels.swap(channels_);
            const std::uint64_t target = added_;
            const bool last = stopping_;
            lock.unlock();
            write_batch(topics, samples, channels);
            lock.lock();
            committed_ = target;
            done_.notify_all();
            if (last)
                return;
        }
    }

    void write_batch(const std::vector<TopicRecord>& topics, const std::vector<SampleRecord>& samples,
                     const std::vector<ChannelRecord>& channels) {
        if (topics.empty() && samples.empty() && channels.empty())
            return;
        sqlite3_exec(db_.get(), "BEGIN", nullptr, nullptr, nullptr);
        for (const TopicRecord& t : topics) {
            sqlite3_bind_text(insert_topic_.get(), 1, t.topic.c_str(), -1, SQLITE_TRANSIENT);
            sqlite3_bind_text(insert_topic_.get(), 2, t.type_name.c_str(), -1, SQLITE_TRANSIENT);
            bind_optional(insert_topic_.get(), 3, t.lifespan_ns);
            sqlite3_bind_int(insert_topic_.get(), 4, t.keyed ? 1 : 0);
            sqlite3_bind_int(insert_topic_.get(), 5, t.reliable ? 1 : 0);
            sqlite3_bind_int64(insert_topic_.get(), 6, t.discovered_ns);
            step(insert_topic_.get());
            if (!t.announced_idl.empty()) {
                sqlite3_bind_text(insert_announced_type_.get(), 1, t.type_name.c_str(), -1, SQLITE_TRANSIENT);
                sqlite3_bind_text(insert_announced_type_.get(), 2, t.announced_idl.c_str(), -1, SQLITE_TRANSIENT);
                step(insert_announced_type_.get());
            }
        }
        for (const SampleRecord& s : samples) {
            if (s.backfill) {
                write_backfilled(s);
                continue;
            }
            bind_sample(insert_sample_.get(), s);
            if (step(insert_sample_.get()))
                ++rows_written;
        }
        for (const ChannelRecord& c : channels) {
            sqlite3_bind_int64(insert_channel_.get(), 1, c.time_ns);
            sqlite3_bind_double(insert_channel_.get(), 2, c.channel_bps);
            sqlite3_bind_double(insert_channel_.get(), 3, c.newcomer_bps);
            bind_text_or_null(insert_channel_.get(), 4, c.verdict);
            bind_optional(insert_channel_.get(), 5, c.delivered_bps);
            bind_optional(insert_channel_.get(), 6, c.queueing_ns);
            step(insert_channel_.get());
            for (const GrantRecord& g : c.grants) {
                sqlite3_bind_int64(insert_grant_.get(), 1, c.time_ns);
                sqlite3_bind_text(insert_grant_.get(), 2, g.gateway.c_str(), -1, SQLITE_TRANSIENT);
                bind_text_or_null(insert_grant_.get(), 3, g.robot);
                sqlite3_bind_double(insert_grant_.get(), 4, g.rate_bps);
                step(insert_grant_.get());
            }
        }
        if (sqlite3_exec(db_.get(), "COMMIT", nullptr, nullptr, nullptr) == SQLITE_OK) {
            acknowledge();
            return;
        }
        report_error("commit");
        // Rolled back: the robot sends the rows again. Otherwise the transaction is still open (SQLITE_BUSY) and the
        // next batch's COMMIT holds these rows too, so their acknowledgements wait for it.
        if (sqlite3_get_autocommit(db_.get()))
            unacknowledged_.clear();
    }

    /// Inserts a backfilled sample unless its row is stored already; either way its acknowledgement waits for the
    /// commit.
    void write_backfilled(const SampleRecord& s) {
        bind_sample(insert_backfill_.get(), s);
        sqlite3_bind_text(insert_backfill_.get(), 8, s.backfill->log_id.c_str(), -1, SQLITE_TRANSIENT);
        sqlite3_bind_int64(insert_backfill_.get(), 9, s.backfill->row_id);
        bind_text_or_null(insert_backfill_.get(), 10, s.backfill->reason);
        if (!step(insert_backfill_.get()))
            return;
        if (sqlite3_changes(db_.get()) > 0)
            ++rows_written;
        else
            ++duplicate_backfill_rows;
        unacknowledged_.emplace_back(s.backfill->log_id, s.backfill->row_id);
    }

    /// After a commit; on the writer thread, with mutex_ not held, so the callback may call add(). Under
    /// stored_backfill_mutex_: whoever replaces the callback (its owner, going away) waits for the call to end.
    void acknowledge() {
        std::lock_guard<std::mutex> lock(stored_backfill_mutex_);
        if (stored_backfill_)
            for (const auto& [log_id, row_id] : unacknowledged_)
                stored_backfill_(log_id, row_id);
        unacknowledged_.clear();
    }

    bool step(sqlite3_stmt* stmt) {
        const bool ok = sqlite3_step(stmt) == SQLITE_DONE;
        sqlite3_reset(stmt);
        sqlite3_clear_bindings(stmt);
        if (!ok)
            report_error("insert");
        return ok;
    }

    void report_error(const char* what) {
        if (write_errors++ == 0)
            std::fprintf(stderr, "tm-basecamp: SQLite %s failed: %s (further errors only counted)\n", what,
                         sqlite3_errmsg(db_.get()));
    }

    // The statements are finalized before the connection closes: declared after it.
    base::DbPtr db_;
    base::StmtPtr insert_sample_;
    base::StmtPtr insert_backfill_;
    base::StmtPtr insert_topic_;
    base::StmtPtr insert_announced_type_;  ///< the IDL a type's TypeObject gave, for export --mcap
    base::StmtPtr insert_channel_;
    base::StmtPtr insert_grant_;
    std::chrono::milliseconds period_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::condition_variable done_;
    std::vector<TopicRecord> topics_;
    std::vector<SampleRecord> samples_;
    std::vector<ChannelRecord> channels_;
    std::uint64_t added_ = 0;
    std::uint64_t committed_ = 0;
    bool stopping_ = false;
    bool flush_requested_ = false;
    /// Set before samples are added, then read by the writer thread alone.
    std::mutex stored_backfill_mutex_;
    StoredBackfill stored_backfill_;  // under stored_backfill_mutex_
    /// The writer thread's: backfilled rows written since the last commit, to acknowledge once it commits.
    std::vector<std::pair<std::string, std::int64_t>> unacknowledged_;
    std::thread writer_;
};

SampleStore::SampleStore(const std::string& path, const std::string& flag, int commit_period_ms)
    : impl_(std::make_unique<Impl>(path, flag, commit_period_ms)) {}

SampleStore::~SampleStore() = default;

void SampleStore::add_topic(TopicRecord topic) {
    impl_->add_topic(std::move(topic));
}

void SampleStore::add(SampleRecord sample) {
    impl_->add(std::move(sample));
}

void SampleStore::add_channel(const ChannelRecord& channel) {
    impl_->add_channel(channel);
}

void SampleStore::flush() {
    impl_->flush();
}

void SampleStore::on_backfill_stored(StoredBackfill callback) {
    impl_->on_backfill_stored(std::move(callback));
}

std::uint64_t SampleStore::rows_written() const {
    return impl_->rows_written.load();
}

std::uint64_t SampleStore::write_errors() const {
    return impl_->write_errors.load();
}

std::uint64_t SampleStore::duplicate_backfill_rows() const {
    return impl_->duplicate_backfill_rows.load();
}

}  // namespace tgw::basecamp
