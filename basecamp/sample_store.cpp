#include "basecamp/sample_store.hpp"

#include <sqlite3.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <thread>
#include <type_traits>

#include "base/config_error.hpp"

namespace tgw::basecamp {

namespace {

constexpr const char* SCHEMA = R"sql(
PRAGMA journal_mode=WAL;
PRAGMA synchronous=NORMAL;
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

}  // namespace

class SampleStore::Impl {
  public:
    Impl(const std::string& path, const std::string& flag, int commit_period_ms) : period_(commit_period_ms) {
        if (sqlite3_open(path.c_str(), &db_) != SQLITE_OK) {
            const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
            sqlite3_close(db_);
            throw base::ConfigError(flag + ": cannot open '" + path + "': " + why);
        }
        char* error = nullptr;
        if (sqlite3_exec(db_, SCHEMA, nullptr, nullptr, &error) != SQLITE_OK) {
            const std::string why = error ? error : "unknown error";
            sqlite3_free(error);
            sqlite3_close(db_);
            throw base::ConfigError(flag + ": cannot create tables in '" + path + "': " + why);
        }
        sqlite3_prepare_v2(db_,
                           "INSERT INTO samples(topic, type_name, payload, source_ns, receive_ns, lifespan_ns, "
                           "instance) VALUES(?,?,?,?,?,?,?)",
                           -1, &insert_sample_, nullptr);
        sqlite3_prepare_v2(db_,
                           "INSERT OR REPLACE INTO topics(topic, type_name, lifespan_ns, keyed, reliable, "
                           "discovered_ns) VALUES(?,?,?,?,?,?)",
                           -1, &insert_topic_, nullptr);
        sqlite3_prepare_v2(db_, "INSERT OR REPLACE INTO announced_types(type_name, idl) VALUES(?,?)", -1,
                           &insert_announced_type_, nullptr);
        sqlite3_prepare_v2(db_,
                           "INSERT INTO channel(time_ns, channel_bps, newcomer_bps, verdict, delivered_bps, "
                           "queueing_ns) VALUES(?,?,?,?,?,?)",
                           -1, &insert_channel_, nullptr);
        sqlite3_prepare_v2(db_, "INSERT INTO grants(time_ns, gateway, robot, rate_bps) VALUES(?,?,?,?)", -1,
                           &insert_grant_, nullptr);
        writer_ = std::thread([this] { write_loop(); });
    }

    ~Impl() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
        }
        wake_.notify_all();
        writer_.join();
        sqlite3_finalize(insert_sample_);
        sqlite3_finalize(insert_topic_);
        sqlite3_finalize(insert_announced_type_);
        sqlite3_finalize(insert_channel_);
        sqlite3_finalize(insert_grant_);
        sqlite3_close(db_);
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

    std::atomic<std::uint64_t> rows_written{0};
    std::atomic<std::uint64_t> write_errors{0};

  private:
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
        sqlite3_exec(db_, "BEGIN", nullptr, nullptr, nullptr);
        for (const TopicRecord& t : topics) {
            sqlite3_bind_text(insert_topic_, 1, t.topic.c_str(), -1, SQLITE_TRANSIENT);
            sqlite3_bind_text(insert_topic_, 2, t.type_name.c_str(), -1, SQLITE_TRANSIENT);
            bind_optional(insert_topic_, 3, t.lifespan_ns);
            sqlite3_bind_int(insert_topic_, 4, t.keyed ? 1 : 0);
            sqlite3_bind_int(insert_topic_, 5, t.reliable ? 1 : 0);
            sqlite3_bind_int64(insert_topic_, 6, t.discovered_ns);
            step(insert_topic_);
            if (!t.announced_idl.empty()) {
                sqlite3_bind_text(insert_announced_type_, 1, t.type_name.c_str(), -1, SQLITE_TRANSIENT);
                sqlite3_bind_text(insert_announced_type_, 2, t.announced_idl.c_str(), -1, SQLITE_TRANSIENT);
                step(insert_announced_type_);
            }
        }
        for (const SampleRecord& s : samples) {
            sqlite3_bind_text(insert_sample_, 1, s.topic.c_str(), -1, SQLITE_TRANSIENT);
            sqlite3_bind_text(insert_sample_, 2, s.type_name.c_str(), -1, SQLITE_TRANSIENT);
            bind_blob(insert_sample_, 3, s.payload, false);
            sqlite3_bind_int64(insert_sample_, 4, s.source_ns);
            sqlite3_bind_int64(insert_sample_, 5, s.receive_ns);
            bind_optional(insert_sample_, 6, s.lifespan_ns);
            bind_blob(insert_sample_, 7, s.instance, true);
            if (step(insert_sample_))
                ++rows_written;
        }
        for (const ChannelRecord& c : channels) {
            sqlite3_bind_int64(insert_channel_, 1, c.time_ns);
            sqlite3_bind_double(insert_channel_, 2, c.channel_bps);
            sqlite3_bind_double(insert_channel_, 3, c.newcomer_bps);
            bind_text_or_null(insert_channel_, 4, c.verdict);
            bind_optional(insert_channel_, 5, c.delivered_bps);
            bind_optional(insert_channel_, 6, c.queueing_ns);
            step(insert_channel_);
            for (const GrantRecord& g : c.grants) {
                sqlite3_bind_int64(insert_grant_, 1, c.time_ns);
                sqlite3_bind_text(insert_grant_, 2, g.gateway.c_str(), -1, SQLITE_TRANSIENT);
                bind_text_or_null(insert_grant_, 3, g.robot);
                sqlite3_bind_double(insert_grant_, 4, g.rate_bps);
                step(insert_grant_);
            }
        }
        if (sqlite3_exec(db_, "COMMIT", nullptr, nullptr, nullptr) != SQLITE_OK)
            report_error("commit");
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
                         sqlite3_errmsg(db_));
    }

    sqlite3* db_ = nullptr;
    sqlite3_stmt* insert_sample_ = nullptr;
    sqlite3_stmt* insert_topic_ = nullptr;
    sqlite3_stmt* insert_announced_type_ = nullptr;  ///< the IDL a type's TypeObject gave, for export --mcap
    sqlite3_stmt* insert_channel_ = nullptr;
    sqlite3_stmt* insert_grant_ = nullptr;
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

std::uint64_t SampleStore::rows_written() const {
    return impl_->rows_written.load();
}

std::uint64_t SampleStore::write_errors() const {
    return impl_->write_errors.load();
}

}  // namespace tgw::basecamp
