// The samples the schedule wrote through reliable WAN writers, by writer and sequence number, until their deadlines.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <unordered_map>
#include <unordered_set>

#include "base/time.hpp"
#include "core/sample.hpp"

namespace tgw::dds {

/// What the RepairDesk reads a repair's topic and urgency from. A writer numbers its samples in the order it
/// writes them, so each writer's are kept in a deque in that order: noting one appends without allocating a
/// node per sample, finding one is a binary search, and pruning pops the front.
class WrittenSamples {
  public:
    struct Written {
        core::TopicId topic = 0;
        base::SteadyTime deadline{};
    };

    /// Notes sample `sequence` of writer `writer` (its entity id); a sample noted again (a copy of its message
    /// to another reader) is noted anew. `expiring`: a volatile writer's, whose samples are no use past their
    /// deadlines (expiring()).
    void note(std::uint32_t writer, std::int64_t sequence, const Written& written, bool expiring);
    /// The sample's, while its deadline is after `now`; null once past it or never noted.
    const Written* find(std::uint32_t writer, std::int64_t sequence, base::SteadyTime now) const;
    /// Whether `writer` wrote a sample noted as expiring since the last clear().
    bool expiring(std::uint32_t writer) const;
    /// Forgets each writer's oldest samples while they are past their deadlines at `now`, and a writer none of
    /// whose samples is left (its deque's memory with it; expiring() still knows it). A sample with a later
    /// deadline ahead of them keeps them a little longer; find() does not return them.
    void prune(base::SteadyTime now);
    /// Forgets every sample and writer (a new participant's writers number their samples afresh).
    void clear() {
        writers_.clear();
        expiring_.clear();
    }
    /// Samples kept.
    std::size_t size() const;

  private:
    struct Entry {
        std::int64_t sequence;
        Written written;
    };
    /// Each writer's samples by sequence.
    std::unordered_map<std::uint32_t, std::deque<Entry>> writers_;
    /// The writers noted expiring, kept after their samples are pruned.
    std::unordered_set<std::uint32_t> expiring_;
};

}  // namespace tgw::dds
