// What became of each topic's samples, over every bridge it had: the topics bridged now and those retired.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/topic_counters.hpp"
#include "passthrough/ttl_resolver.hpp"

namespace tgw::dds {

/// One row of the gateway's per-topic accounting (Gateway::topic_counts): a topic bridged now, one retired, or
/// the retired topics past RetiredTopics::MAX_NAMED together (named RetiredTopics::OTHERS).
struct TopicCount {
    std::string name;
    passthrough::ResolvedTtl ttl;  ///< the latest bridge's
    /// Every bridge the topic had, summed: received = forwarded + queued + dropped holds for each, so for the sum.
    core::TopicCounters counters;
    bool bridged = false;              ///< bridged now
    std::int32_t matched_readers = 0;  ///< base-camp readers matched now, when bridged
};

/// The counts retired topics left, kept by name so that a topic that comes back adds to its own, and bounded so
/// that topics that come and go cost no memory for good. Not thread-safe: the Gateway holds it under the lock
/// that also covers the scheduler's slots, so that a topic's counts are never seen in both, nor in neither.
class RetiredTopics {
  public:
    /// Retired topics whose counts are kept by name; those of more go into one row, OTHERS.
    static constexpr std::size_t MAX_NAMED = 4096;
    static constexpr const char* OTHERS = "(other retired topics)";

    /// Adds `counts` to the record of `name`, with the TTL its last bridge had.
    void keep(const std::string& name, const passthrough::ResolvedTtl& ttl, const core::TopicCounters& counts);
    /// Every retired record together.
    const core::TopicCounters& total() const { return total_; }
    /// `bridged` (the topics bridged now, their counts in the scheduler), each with its earlier bridges' counts
    /// added, then a row for each retired topic not bridged again, by name, then OTHERS if any.
    std::vector<TopicCount> with(std::vector<TopicCount> bridged) const;

  private:
    struct Record {
        core::TopicCounters counters;
        passthrough::ResolvedTtl ttl;
    };
    std::map<std::string, Record> by_name_;
    Record others_;  ///< beyond MAX_NAMED
    core::TopicCounters total_;
};

}  // namespace tgw::dds
