#include "gateway/dds/topic_accounting.hpp"

#include <set>
#include <utility>

namespace tgw::dds {

void RetiredTopics::keep(const std::string& name, const passthrough::ResolvedTtl& ttl,
                         const core::TopicCounters& counts) {
    total_ += counts;
    auto it = by_name_.find(name);
    if (it == by_name_.end() && by_name_.size() >= MAX_NAMED) {
        others_.counters += counts;
        others_.ttl = ttl;
        return;
    }
    if (it == by_name_.end()) {
        it = by_name_.emplace(name, Record{}).first;
    }
    it->second.counters += counts;
    it->second.ttl = ttl;
}

std::vector<TopicCount> RetiredTopics::with(std::vector<TopicCount> bridged) const {
    std::set<std::string> names;
    for (TopicCount& row : bridged) {
        // A topic that came back: its earlier bridges' counts too.
        if (const auto it = by_name_.find(row.name); it != by_name_.end()) {
            row.counters += it->second.counters;
        }
        names.insert(row.name);
    }
    for (const auto& [name, record] : by_name_) {
        if (names.count(name) == 0) {
            bridged.push_back(TopicCount{name, record.ttl, record.counters, false, 0});
        }
    }
    if (others_.counters.received > 0) {
        bridged.push_back(TopicCount{OTHERS, others_.ttl, others_.counters, false, 0});
    }
    return bridged;
}

}  // namespace tgw::dds
