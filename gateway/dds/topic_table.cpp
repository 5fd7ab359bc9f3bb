#include "gateway/dds/topic_table.hpp"

#include <utility>

namespace tgw::dds {

void TopicTable::add(std::shared_ptr<TopicBridge> bridge) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const core::TopicId id = bridge->id();
        if (by_id_.size() <= id) {
            by_id_.resize(id + 1, nullptr);
        }
        by_id_[id] = bridge;
        by_name_.emplace(bridge->name(), std::move(bridge));
    }
    changed_.notify_all();
}

std::shared_ptr<TopicBridge> TopicTable::remove(const std::string& name) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = by_name_.find(name);
    if (it == by_name_.end()) {
        return nullptr;
    }
    std::shared_ptr<TopicBridge> bridge = std::move(it->second);
    by_name_.erase(it);
    if (bridge->id() < by_id_.size() && by_id_[bridge->id()] == bridge) {
        by_id_[bridge->id()] = nullptr;
    }
    return bridge;
}

std::shared_ptr<TopicBridge> TopicTable::find(core::TopicId id) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return id < by_id_.size() ? by_id_[id] : nullptr;
}

std::shared_ptr<TopicBridge> TopicTable::find(const std::string& name) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = by_name_.find(name);
    return it == by_name_.end() ? nullptr : it->second;
}

std::vector<std::shared_ptr<TopicBridge>> TopicTable::all() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::shared_ptr<TopicBridge>> out;
    out.reserve(by_name_.size());
    for (const auto& [name, bridge] : by_name_) {
        out.push_back(bridge);
    }
    return out;
}

std::size_t TopicTable::size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return by_name_.size();
}

bool TopicTable::wait_for(const std::string& name, std::chrono::milliseconds timeout) const {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] { return by_name_.count(name) != 0; });
}

}  // namespace tgw::dds
