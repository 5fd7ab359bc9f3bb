// A recording made by tm-basecamp record or relay --out, or a mission archive made by merge, read back in the
// order of the mission: what export turns into an MCAP file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "base/sqlite_handles.hpp"
#include "basecamp/sample/sample_consumer.hpp"

namespace tgw::basecamp {

class RecordingReader {
  public:
    /// Opens the recording or mission archive at `path` read-only. Throws base::ConfigError naming `flag` and the
    /// file when it cannot, or the file is neither.
    RecordingReader(const std::string& path, const std::string& flag);
    RecordingReader(const RecordingReader&) = delete;
    RecordingReader& operator=(const RecordingReader&) = delete;

    /// Hands `into` every topic (with the IDL its publisher's TypeObject gave, where the recording has it), then
    /// every sample in order of receive time; a backfilled sample (SampleRecord::backfill) at its source time, when
    /// the robot produced it. From a mission archive, the samples that stayed on the robot and were not backfilled
    /// come as topics of their own: "dropped/REASON/TOPIC" at the time the gateway logged them, with their payload,
    /// and "lost/TOPIC" (no payload, no type) at the time the gateway forwarded them. The number of samples. Throws
    /// base::ConfigError when reading fails.
    std::uint64_t read(SampleConsumer& into);

    bool is_mission_archive() const { return archive_; }

    /// A mission archive's link rates (the gateway's log, table link_rates): (wall ns, sensed bit/s) in time order;
    /// empty for a recording, or an archive of a log that had none.
    std::vector<std::pair<std::int64_t, double>> link_rates() const;

  private:
    std::uint64_t read_recording(SampleConsumer& into);
    std::uint64_t read_archive(SampleConsumer& into);

    std::string path_;
    std::string flag_;
    base::DbPtr db_;
    bool archive_ = false;
};

}  // namespace tgw::basecamp
