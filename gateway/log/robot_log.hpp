#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "gateway/core/drop_reason.hpp"
#include "gateway/core/sample.hpp"

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
};

/// The link rate the gateway plans with from `at` on: the sensor's, and the budget it gives.
struct RateRecord {
    base::WallTime at;
    double sensed_bps = 0;
    double budget_bps = 0;
};

/// The on-robot log: an SQLite file with one row per sample not sent (table dropped_samples: topic, type name,
/// payload, instance key, source time, arrival, deadline, logged time, reason) and one per sample sent (table
/// forwarded_samples: the same without payload and reason, with the payload's size and the time it was
/// written), and the link's rate over time (table link_rates). Appends are buffered and written in batched transactions
/// by a background thread, so the gateway's path never waits on the disk; flush() and the destructor write everything
/// still buffered.
class RobotLog {
  public:
    /// Opens or creates `path` (WAL mode). Throws base::ConfigError naming the file if it cannot. With
    /// `max_bytes` (0: no cap), the file stops growing there: once its rows take more, the oldest go, those of
    /// forwarded_samples first (they only say that a sample left), then those of dropped_samples, down to 90 % of
    /// the cap; the meta table counts them (pruned_forwarded_rows, pruned_dropped_rows).
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
    /// Blocks until everything appended so far is committed to the file.
    void flush();

    /// Sample rows committed, of both sample tables.
    std::uint64_t rows_written() const;
    std::uint64_t write_errors() const;
    /// Rows deleted to keep the file under its cap, of both sample tables, since it was opened.
    std::uint64_t pruned_rows() const;
    const std::string& path() const;

  private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace tgw::log
