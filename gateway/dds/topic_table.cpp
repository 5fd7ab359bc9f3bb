#include "gateway/dds/topic_table.hpp"

#include <utility>

namespace tgw::dds {

void TopicTable::add(std::unique_ptr<TopicBridge> bridge) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const core::TopicId id = bridge->id();
        if (by_id_.size() <= id) {
            by_id_.resize(id + 1, nullptr);
        }
        by_id_[id] = bridge.get();
        by_name_.emplace(bridge->name(), std::move(bridge));
    }
    changed_.notify_all();
}

TopicBridge* TopicTable::find(core::TopicId id) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return id < by_id_.size() ? by_id_[id] : nullptr;
}

TopicBridge* TopicTable::find(const std::string& name) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = by_name_.find(name);
    return it == by_name_.end() ? nullptr : it->second.get();
}

std::vector<TopicBridge*> TopicTable::all() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<TopicBridge*> out;
    out.reserve(by_name_.size());
    for (const auto& [name, bridge] : by_name_) {
        out.push_back(bridge.get());
    }
    return out;
}

bool TopicTable::wait_for(const std::string& name, std::chrono::milliseconds timeout) const {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] { return by_name_.count(name) != 0; });
}

}  // namespace tgw::dds
