#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "basecamp/sample_consumer.hpp"
#include "basecamp/sample_record.hpp"

namespace tgw::basecamp {

/// The base camp's recording: an SQLite file in WAL mode with a `topics` and a `samples` table, and where the relay
/// shares a fleet's channel a `channel` table (a row per round of grants) and a `grants` table (a row per gateway
/// per round). Rows are
/// buffered and committed by a background thread every `commit_period_ms`, so a kill loses at most that
/// much; the DDS threads that call add() never wait on the disk.
class SampleStore final : public SampleConsumer {
  public:
    /// Creates or opens `path`. Throws base::ConfigError naming `flag` and the file if it cannot.
    SampleStore(const std::string& path, const std::string& flag, int commit_period_ms = 200);
    ~SampleStore();
    SampleStore(const SampleStore&) = delete;
    SampleStore& operator=(const SampleStore&) = delete;

    /// Never throws; failures are counted.
    void add_topic(TopicRecord topic) override;
    void add(SampleRecord sample) override;
    void add_channel(const ChannelRecord& channel) override;
    /// Blocks until everything added so far is committed.
    void flush();

    std::uint64_t rows_written() const;
    std::uint64_t write_errors() const;

  private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace tgw::basecamp
