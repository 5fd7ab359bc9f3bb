#include "gateway/log/backfill_reader.hpp"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <limits>
#include <utility>

#include "base/config_error.hpp"

namespace tgw::log {

namespace {

/// How long a read waits when the file is busy (the writer's checkpoint, a recovery); in WAL mode, rarely at all.
constexpr int READ_BUSY_TIMEOUT_MS = 2000;

// The partial index dropped_backfill_due (robot_log.cpp) answers the WHERE clause without reading the rows the
// camp has, nor a row's kind, which stands after its payload; length() reads a blob's size, not its bytes. Only
// data is backfilled: a dispose or unregister stays in the log.
constexpr const char* UNACKNOWLEDGED_SQL =
    "SELECT id, topic, source_time_ns, deadline_ns, length(payload) FROM dropped_samples "
    "WHERE acked_ns IS NULL AND kind = 'data' AND id > ?1 ORDER BY id LIMIT ?2;";

constexpr const char* READ_DROPPED_SQL =
    "SELECT topic, type_name, payload, instance_key, source_time_ns, deadline_ns, reason, kind FROM dropped_samples "
    "WHERE id = ?1;";

/// Resets a statement when the read ends, however it ends: a statement left stepping would keep its read
/// snapshot, and with it the WAL, from being checkpointed.
class ResetOnExit {
  public:
    explicit ResetOnExit(sqlite3_stmt* stmt) : stmt_(stmt) {}
    ~ResetOnExit() {
        sqlite3_reset(stmt_);
        sqlite3_clear_bindings(stmt_);
    }
    ResetOnExit(const ResetOnExit&) = delete;
    ResetOnExit& operator=(const ResetOnExit&) = delete;

  private:
    sqlite3_stmt* stmt_;
};

std::string column_text(sqlite3_stmt* stmt, int column) {
    const auto* data = reinterpret_cast<const char*>(sqlite3_column_text(stmt, column));
    return data != nullptr ? std::string(data, static_cast<std::size_t>(sqlite3_column_bytes(stmt, column)))
                           : std::string();
}

}  // namespace

BackfillReader::BackfillReader(const std::string& path) : path_(path) {
    sqlite3* raw = nullptr;
    const int rc = sqlite3_open_v2(path_.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
    db_.reset(raw);  // a handle even on failure, to carry the message
    if (rc == SQLITE_OK) {
        sqlite3_extended_result_codes(db_.get(), 1);
        sqlite3_busy_timeout(db_.get(), READ_BUSY_TIMEOUT_MS);
        unacknowledged_ = base::prepare_persistent(db_.get(), UNACKNOWLEDGED_SQL);
        read_dropped_ = base::prepare_persistent(db_.get(), READ_DROPPED_SQL);
    }
    if (unacknowledged_ == nullptr || read_dropped_ == nullptr)
        throw base::ConfigError("on-robot log " + path_ + ": cannot open it for backfill's reads: " +
                                (db_ != nullptr ? sqlite3_errmsg(db_.get()) : "out of memory"));
}

std::vector<BackfillCandidate> BackfillReader::unacknowledged(std::int64_t after_row_id,
                                                              std::size_t max_rows) noexcept {
    std::vector<BackfillCandidate> rows;
    std::lock_guard<std::mutex> lock(mutex_);
    sqlite3_stmt* stmt = unacknowledged_.get();
    ResetOnExit reset(stmt);
    const auto limit = static_cast<sqlite3_int64>(
        std::min<std::size_t>(max_rows, static_cast<std::size_t>(std::numeric_limits<sqlite3_int64>::max())));
    sqlite3_bind_int64(stmt, 1, after_row_id);
    sqlite3_bind_int64(stmt, 2, limit);
    try {
        int rc = SQLITE_ROW;
        while ((rc = sqlite3_step(stmt)) == SQLITE_ROW) {
            BackfillCandidate row;
            row.row_id = sqlite3_column_int64(stmt, 0);
            row.topic = column_text(stmt, 1);
            row.source_time = base::wall_from_ns(sqlite3_column_int64(stmt, 2));
            row.deadline = base::wall_from_ns(sqlite3_column_int64(stmt, 3));
            row.payload_bytes = static_cast<std::size_t>(sqlite3_column_int64(stmt, 4));
            rows.push_back(std::move(row));
        }
        if (rc != SQLITE_DONE)
            fail_read_nts(sqlite3_errmsg(db_.get()));
    } catch (const std::exception& e) {
        fail_read_nts(e.what());  // only allocation throws: the rows read so far are still good
    }
    return rows;
}

std::optional<StoredSample> BackfillReader::read_dropped(std::int64_t row_id) noexcept {
    std::lock_guard<std::mutex> lock(mutex_);
    sqlite3_stmt* stmt = read_dropped_.get();
    ResetOnExit reset(stmt);
    sqlite3_bind_int64(stmt, 1, row_id);
    const int rc = sqlite3_step(stmt);
    if (rc != SQLITE_ROW) {
        if (rc != SQLITE_DONE)
            fail_read_nts(sqlite3_errmsg(db_.get()));
        return std::nullopt;
    }
    try {
        StoredSample row;
        row.row_id = row_id;
        row.topic = column_text(stmt, 0);
        row.type_name = column_text(stmt, 1);
        const auto* payload = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt, 2));
        row.payload.assign(payload, payload + (payload != nullptr ? sqlite3_column_bytes(stmt, 2) : 0));
        const auto* key = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt, 3));
        // A key of another size is not one this gateway wrote: the row is sent as unkeyed rather than misread.
        if (key != nullptr && static_cast<std::size_t>(sqlite3_column_bytes(stmt, 3)) == row.key.bytes.size()) {
            std::copy(key, key + row.key.bytes.size(), row.key.bytes.begin());
            row.key.valid = true;
        }
        row.source_time = base::wall_from_ns(sqlite3_column_int64(stmt, 4));
        row.deadline = base::wall_from_ns(sqlite3_column_int64(stmt, 5));
        row.reason = column_text(stmt, 6);
        row.kind = core::sample_kind_named(column_text(stmt, 7)).value_or(core::SampleKind::data);
        return row;
    } catch (const std::exception& e) {
        fail_read_nts(e.what());
        return std::nullopt;
    }
}

void BackfillReader::fail_read_nts(const char* why) noexcept {
    if (failure_reported_)
        return;
    failure_reported_ = true;
    std::fprintf(stderr, "on-robot log %s: backfill read failed: %s (further failures are not reported)\n",
                 path_.c_str(), why);
}

}  // namespace tgw::log
