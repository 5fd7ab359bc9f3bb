#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "basecamp/sample/sample_consumer.hpp"
#include "basecamp/sample/sample_record.hpp"

namespace tgw::basecamp {

/// The base camp's recording: an SQLite file in WAL mode with a `topics` and a `samples` table, and where the relay
/// shares a fleet's channel a `channel` table (a row per round of grants) and a `grants` table (a row per gateway
/// per round). Rows are
/// buffered and committed by a background thread every `commit_period_ms`, so a kill loses at most that
/// much; the DDS threads that call add() never wait on the disk.
///
/// Backfilled samples (SampleRecord::backfill) go to `samples` too, flagged `backfilled` with their on-robot log row
/// (`log_id`, `row_id`) and `drop_reason`; a UNIQUE index on (log_id, row_id) stores each row once, however often
/// it arrives. An older recording gains these columns when opened.
class SampleStore final : public SampleConsumer {
  public:
    /// Told that the robot's log row (log_id, row_id) is in the recording: called after the transaction that stored
    /// it, or found it already stored, has committed.
    using StoredBackfill = std::function<void(const std::string& log_id, std::int64_t row_id)>;

    /// Creates or opens `path`. Throws base::ConfigError naming `flag` and the file if it cannot.
    SampleStore(const std::string& path, const std::string& flag, int commit_period_ms = 200);
    ~SampleStore();
    SampleStore(const SampleStore&) = delete;
    SampleStore& operator=(const SampleStore&) = delete;

    /// Never throws; failures are counted.
    void add_topic(TopicRecord topic) override;
    void add(SampleRecord sample) override;
    void add_channel(const ChannelRecord& channel) override;
    /// Blocks until everything added so far is committed, and its backfilled rows acknowledged.
    void flush();

    /// Sets what acknowledges backfilled rows; set it before adding samples. It is called on the store's writer
    /// thread, once per backfilled sample added (a duplicate included, since the robot may have missed the first
    /// acknowledgement), after the commit that holds the row and never when that commit failed, with no lock of
    /// add()'s held: it may write to DDS or call add(), but not flush(), and must not throw. The destructor commits
    /// the last batch, so it may be called until the store is destroyed, or until it is replaced: replacing it waits
    /// for a call in progress.
    void on_backfill_stored(StoredBackfill callback);

    /// Samples inserted; backfilled duplicates are not.
    std::uint64_t rows_written() const;
    std::uint64_t write_errors() const;
    /// Backfilled samples whose (log_id, row_id) the recording already held, which were not stored again.
    std::uint64_t duplicate_backfill_rows() const;

  private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace tgw::basecamp
