#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace tgw::basecamp {

/// A topic as discovery described its writer.
struct TopicRecord {
    std::string topic;
    std::string type_name;
    std::optional<std::int64_t> lifespan_ns;  ///< the writer's declared Lifespan; empty when infinite
    bool keyed = false;
    bool reliable = false;
    std::int64_t discovered_ns = 0;  ///< wall clock
};

/// One received sample. Times are wall clock, nanoseconds since the Unix epoch.
struct SampleRecord {
    std::string topic;
    std::string type_name;
    std::vector<std::uint8_t> payload;  ///< serialized, as received, encapsulation header included
    std::int64_t source_ns = 0;
    std::int64_t receive_ns = 0;
    std::optional<std::int64_t> lifespan_ns;
    std::vector<std::uint8_t> instance;  ///< 16-byte instance handle of keyed topics, else empty
};

/// The base camp's recording: an SQLite file in WAL mode with a `topics` and a `samples` table. Rows are
/// buffered and committed by a background thread every `commit_period_ms`, so a kill loses at most that
/// much; the DDS threads that call add() never wait on the disk.
class SampleStore {
  public:
    /// Creates or opens `path`. Throws core::ConfigError naming `flag` and the file if it cannot.
    SampleStore(const std::string& path, const std::string& flag, int commit_period_ms = 200);
    ~SampleStore();
    SampleStore(const SampleStore&) = delete;
    SampleStore& operator=(const SampleStore&) = delete;

    /// Never throws; failures are counted.
    void add_topic(TopicRecord topic);
    void add(SampleRecord sample);
    /// Blocks until everything added so far is committed.
    void flush();

    std::uint64_t rows_written() const;
    std::uint64_t write_errors() const;

  private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace tgw::basecamp
