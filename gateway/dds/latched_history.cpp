#include "gateway/dds/latched_history.hpp"

#include <iterator>

namespace tgw::dds {

LatchedHistory::Instance LatchedHistory::instance_of(const core::Sample& change) {
    return {change.key.valid, change.key.valid ? change.key.bytes : std::array<std::uint8_t, 16>{}};
}

void LatchedHistory::keep(const core::Sample& change) {
    // Runs for every sample a latched writer sends: an instance seen before takes the new change into its own
    // node, whose payload keeps its capacity. No allocation once every instance has been written.
    slot_for(change) = change;
}

void LatchedHistory::keep_taking_payload(core::Sample& change) {
    std::vector<std::uint8_t> payload = std::move(change.payload);  // leaves it empty
    core::Sample& slot = slot_for(change);
    slot = change;  // without a payload: no copy
    slot.payload = std::move(payload);
}

core::Sample& LatchedHistory::slot_for(const core::Sample& change) {
    const Instance instance = instance_of(change);
    if (const auto found = by_instance_.find(instance); found != by_instance_.end()) {
        order_.splice(order_.end(), order_, found->second);
        return *found->second;
    }
    if (order_.size() >= max_instances_ && !order_.empty()) {
        by_instance_.erase(instance_of(order_.front()));
        order_.pop_front();
    }
    order_.emplace_back();
    by_instance_.emplace(instance, std::prev(order_.end()));
    return order_.back();
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
