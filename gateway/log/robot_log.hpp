#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/drop_reason.hpp"
#include "core/sample.hpp"

namespace tgw::log {

/// One sample that was not sent, with its times on the wall clock (the steady times of the core converted at
/// the edge, so the file can be read against the base camp's recording).
struct LogRecord {
    std::string_view topic;
    std::string_view type_name;
    const core::Sample* sample = nullptr;  ///< payload and instance key; not owned
    core::DropReason reason = core::DropReason::expired;
    base::WallTime arrival;
    base::WallTime deadline;
    base::WallTime logged_at;
};

/// One sample written to the WAN, with its times on the wall clock. Its payload is not kept: the row only has to
/// say that the sample left the robot, so that the base camp's recording can tell a sample lost on the link from
/// one never produced (tm-basecamp merge), and a row without payload costs the forwarding path little.
struct ForwardRecord {
    std::string_view topic;
    std::string_view type_name;
    const core::Sample* sample = nullptr;  ///< instance key, source time and payload size; not owned
    base::WallTime arrival;
    base::WallTime deadline;
    base::WallTime forwarded_at;
    /// The payload's size when the sample no longer holds it (a latched writer's history took it).
    std::optional<std::size_t> payload_bytes;
};

/// The link rate the gateway plans with from `at` on: the sensor's, and the budget it gives.
struct RateRecord {
    base::WallTime at;
    double sensed_bps = 0;
    double budget_bps = 0;
};

/// A dropped sample the base camp has not acknowledged yet, as the backfill sender plans with it.
struct BackfillCandidate {
    /// dropped_samples.id, never given twice, not even once its row is pruned: with log_id(), it names the row for
    /// ever.
    std::int64_t row_id = 0;
    std::string topic;
    base::WallTime source_time;
    base::WallTime deadline;
    std::size_t payload_bytes = 0;  ///< 0 for a sample without payload (a dispose or unregister)
};

/// One row of dropped_samples read back whole, to be sent to the base camp.
struct StoredSample {
    std::int64_t row_id = 0;
    std::string topic;
    std::string type_name;
    std::vector<std::uint8_t> payload;
    core::InstanceKey key;                           ///< not valid when the sample had none
    core::SampleKind kind = core::SampleKind::data;  ///< dropped_samples.kind
    base::WallTime source_time;
    base::WallTime deadline;
    std::string reason;  ///< the DropReason's name, as core::to_string() gives it
};

/// The on-robot log: an SQLite file with one row per sample not sent (table dropped_samples: topic, type name,
/// payload, instance key, source time, arrival, deadline, logged time, reason, and for backfill when the base camp
/// acknowledged the row, how often it was sent and when last, and its kind: data, dispose or unregister) and one per
/// sample sent (table forwarded_samples: the same without payload, reason and backfill columns, with the payload's size
/// and the time it was written), and the link's rate over time (table link_rates). The meta table names the file
/// (log_id). Appends and backfill's marks are buffered and written in batched transactions by a background thread, so
/// the gateway's path never waits on the disk; flush() and the destructor write everything still buffered. Backfill's
/// reads use a connection of their own.
class RobotLog {
  public:
    /// Opens or creates `path` (WAL mode); a file written before backfill gains its columns and a log_id, and
    /// keeps its rows. Throws base::ConfigError naming the file if it cannot. With `max_bytes` (0: no cap), the
    /// file stops growing there: once its rows take more, the oldest go, down to 90 % of the cap: first the
    /// dropped rows the base camp acknowledged (it has their payload, and they are the large rows), then those of
    /// forwarded_samples (they only say that a sample left), then the unacknowledged dropped rows. The meta table
    /// counts them (pruned_acknowledged_rows, pruned_forwarded_rows, pruned_dropped_rows).
    explicit RobotLog(const std::string& path, std::uint64_t max_bytes = 0);
    ~RobotLog();

    RobotLog(const RobotLog&) = delete;
    RobotLog& operator=(const RobotLog&) = delete;

    /// Copies the record into the buffer. Never throws; a failed write is counted and reported once.
    void append(const LogRecord& record);
    /// Copies the record, without the payload, into the buffer. Never throws; a failed write is counted and
    /// reported once, as for append().
    void append_forwarded(const ForwardRecord& record);
    /// Copies the rate into the buffer (table link_rates: time, sensed and budget bit/s). Never throws.
    void append_rate(const RateRecord& record);
    /// Counts a send of the dropped row `row_id` at `at` (sends + 1, last_sent_ns). Buffered and written like
    /// append(); never throws. A row already pruned is left as it is: gone.
    void mark_sent(std::int64_t row_id, base::WallTime at);
    /// Marks the dropped rows `first_row_id` to `last_row_id` (both included) as stored by the base camp at `at`,
    /// those not marked yet: from then on they are the first to go at the cap. Buffered and written like
    /// append(); never throws.
    void mark_acknowledged(std::int64_t first_row_id, std::int64_t last_row_id, base::WallTime at);
    /// Blocks until everything appended or marked so far is committed to the file.
    void flush();

    /// Up to `max_rows` committed data rows of dropped_samples (no dispose or unregister: the camp records none)
    /// that the base camp has not acknowledged, with an id
    /// above `after_row_id` (0: from the first; the last id returned: the next page), by id ascending. Callable
    /// from any thread: it reads the last commit on a connection of its own and never waits for the writer's
    /// batches. Never throws; on a read failure, the rows read so far (reported once on stderr).
    std::vector<BackfillCandidate> unacknowledged(std::int64_t after_row_id, std::size_t max_rows);
    /// The committed dropped row `row_id`, whole; nullopt when there is none (pruned, or never written) or it
    /// cannot be read (reported once on stderr). Callable from any thread, never throws, as unacknowledged().
    std::optional<StoredSample> read_dropped(std::int64_t row_id);

    /// The file's id: 128 random bits as 32 lowercase hex characters, made when the file was created (or when a
    /// file from before backfill was first reopened) and the same for as long as the file lives.
    std::string log_id() const;

    /// Sample rows committed, of both sample tables.
    std::uint64_t rows_written() const;
    std::uint64_t write_errors() const;
    /// Rows deleted to keep the file under its cap, of both sample tables, since it was opened.
    std::uint64_t pruned_rows() const;
    /// Dropped rows that mark_acknowledged() marked, committed, since the log was opened (not those of an earlier
    /// run in the file); a row acknowledged twice counts once.
    std::uint64_t acknowledged_rows() const;
    const std::string& path() const;

  private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace tgw::log
