#include "gateway/dds/latched_history.hpp"

#include <iterator>

namespace tgw::dds {

LatchedHistory::Instance LatchedHistory::instance_of(const core::Sample& change) {
    return {change.key.valid, change.key.valid ? change.key.bytes : std::array<std::uint8_t, 16>{}};
}

void LatchedHistory::keep(const core::Sample& change) {
    // Runs for every sample a latched writer sends: an instance seen before takes the new change into its own
    // node, whose payload keeps its capacity, and the node moves to the back. No allocation once every instance
    // has been written.
    const Instance instance = instance_of(change);
    if (const auto found = by_instance_.find(instance); found != by_instance_.end()) {
        *found->second = change;
        order_.splice(order_.end(), order_, found->second);
        return;
    }
    if (order_.size() >= max_instances_ && !order_.empty()) {
        by_instance_.erase(instance_of(order_.front()));
        order_.pop_front();
    }
    order_.push_back(change);
    by_instance_.emplace(instance, std::prev(order_.end()));
}

std::vector<core::Sample> LatchedHistory::live(base::WallTime now, std::optional<base::Duration> lifespan) const {
    std::vector<core::Sample> out;
    out.reserve(order_.size());
    for (const core::Sample& change : order_) {
        if (!lifespan || change.source_time + *lifespan >= now) {
            out.push_back(change);
        }
    }
    return out;
}

}  // namespace tgw::dds
