#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace tgw::basecamp {

/// A DDS GUID: the participant's 12-byte prefix, then the 4-byte entity id.
using WriterGuid = std::array<std::uint8_t, 16>;
using ParticipantPrefix = std::array<std::uint8_t, 12>;

/// "01.0f.ab...": the prefix as Fast DDS prints GUIDs.
std::string prefix_text(const ParticipantPrefix& prefix);

/// What one participant's writers delivered, cumulative.
struct DeliveryTotals {
    std::uint64_t received_samples = 0;
    std::uint64_t received_bytes = 0;
    std::uint64_t lost_samples = 0;
};

/// Counts, per sending participant, the samples received from its writers and those lost on the way: a gap in
/// a writer's sequence numbers is samples written and never received (best effort drops them for good). The
/// first sample of a writer starts its count, so what it wrote before the reader matched is not a loss. A
/// sample that arrives after a later one fills its gap again. Thread-safe: readers of several topics add at once.
class DeliveryTally {
  public:
    /// One received sample of `bytes` serialized bytes with the writer's `sequence` number.
    void add(const WriterGuid& writer, std::uint64_t sequence, std::uint64_t bytes);

    /// The totals per sending participant.
    std::map<ParticipantPrefix, DeliveryTotals> totals() const;

  private:
    struct WriterState {
        std::uint64_t next_sequence = 0;  ///< the sequence number expected next
        std::uint64_t open_gaps = 0;      ///< samples counted lost that may still arrive late
    };

    mutable std::mutex mutex_;
    std::map<WriterGuid, WriterState> writers_;
    std::map<ParticipantPrefix, DeliveryTotals> totals_;
};

}  // namespace tgw::basecamp
