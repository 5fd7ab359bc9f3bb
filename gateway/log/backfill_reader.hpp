#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "base/sqlite_handles.hpp"
#include "gateway/log/robot_log.hpp"

namespace tgw::log {

/// The backfill sender's reads of an on-robot log (RobotLog's unacknowledged() and read_dropped()).
///
/// It has a read-only connection of its own rather than sharing the writer's under a mutex: in WAL mode a reader
/// works on the last commit while the writer appends, so a read never waits for a batch nor holds one up, and it
/// cannot see a batch the writer has begun and not committed, as the writer's own connection would. A mutex
/// serializes the callers of its one connection and its kept statements.
class BackfillReader {
  public:
    /// Opens `path`, which RobotLog has created and migrated. Throws base::ConfigError naming the file.
    explicit BackfillReader(const std::string& path);

    BackfillReader(const BackfillReader&) = delete;
    BackfillReader& operator=(const BackfillReader&) = delete;

    /// As RobotLog::unacknowledged().
    std::vector<BackfillCandidate> unacknowledged(std::int64_t after_row_id, std::size_t max_rows) noexcept;
    /// As RobotLog::read_dropped().
    std::optional<StoredSample> read_dropped(std::int64_t row_id) noexcept;

  private:
    /// Reports the first read failure on stderr; the later ones would only repeat it.
    void fail_read_nts(const char* why) noexcept;

    const std::string path_;
    std::mutex mutex_;
    base::DbPtr db_;
    base::StmtPtr unacknowledged_;
    base::StmtPtr read_dropped_;
    bool failure_reported_ = false;
};

}  // namespace tgw::log
