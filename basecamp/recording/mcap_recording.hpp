// A recording as an MCAP file: one channel per topic, each message's bytes as received (CDR, encapsulation header
// included), log time = receive time, publish time = the source timestamp, and an omgidl schema per type that
// Foxglove and the MCAP libraries decode field by field.
#pragma once

#include <map>
#include <mutex>
#include <string>

#include "basecamp/recording/mcap_writer.hpp"
#include "basecamp/sample/sample_consumer.hpp"
#include "types/type_library.hpp"

namespace tgw::basecamp {

class McapRecording final : public SampleConsumer {
  public:
    /// Creates `path` (see McapWriter). A type's schema is its IDL from `types` (the project's, --idl), else the
    /// IDL its publisher's TypeObject gave (TopicRecord::announced_idl); a type with neither has a channel
    /// without schema.
    McapRecording(const std::string& path, const std::string& flag, types::TypeLibrary types,
                  McapCompression compression = McapCompression::none, std::size_t chunk_bytes = 1 << 20);

    void add_topic(TopicRecord topic) override;
    /// A sample of a topic not added before gets a channel from what the sample says of it.
    void add(SampleRecord sample) override;

    /// Writes the summary and closes the file; false when a write failed.
    bool close();

    std::uint64_t messages() const;
    /// Topics whose type had no schema to give.
    std::uint64_t channels_without_schema() const;

  private:
    std::uint16_t channel_nts(const TopicRecord& topic);
    std::uint16_t schema_nts(const TopicRecord& topic);

    const types::TypeLibrary types_;
    mutable std::mutex mutex_;
    McapWriter writer_;
    std::map<std::string, std::uint16_t> channels_;  ///< by topic
    std::map<std::string, std::uint16_t> schemas_;   ///< by type name; 0: none
    std::uint64_t without_schema_ = 0;
};

}  // namespace tgw::basecamp
