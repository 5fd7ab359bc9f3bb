// A recording made by tm-basecamp record or relay --out, read back in the order it was received: what export
// turns into an MCAP file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "basecamp/sample_consumer.hpp"

struct sqlite3;

namespace tgw::basecamp {

class RecordingReader {
  public:
    /// Opens the recording at `path` read-only. Throws base::ConfigError naming `flag` and the file when it cannot,
    /// or the file is not a recording.
    RecordingReader(const std::string& path, const std::string& flag);
    ~RecordingReader();
    RecordingReader(const RecordingReader&) = delete;
    RecordingReader& operator=(const RecordingReader&) = delete;

    /// Hands `into` every topic (with the IDL its publisher's TypeObject gave, where the recording has it), then
    /// every sample in order of receive time. The number of samples. Throws base::ConfigError when reading fails.
    std::uint64_t read(SampleConsumer& into);

  private:
    std::string path_;
    std::string flag_;
    sqlite3* db_ = nullptr;
};

}  // namespace tgw::basecamp
