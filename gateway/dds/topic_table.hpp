#pragma once

#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/sample.hpp"
#include "gateway/dds/topic_bridge.hpp"

namespace tgw::dds {

/// The gateway's bridged topics, found by name (discovery) or by TopicId (a sample's way out, the on-robot log).
/// A bridge leaves the table when its topic is retired (Gateway); whoever found it before holds it until done with
/// it. Thread-safe.
class TopicTable {
  public:
    /// `bridge`'s name and id must not be in the table.
    void add(std::shared_ptr<TopicBridge> bridge);
    /// Takes the bridge of `name` out of the table; nullptr when unknown. Its id may then be another topic's.
    std::shared_ptr<TopicBridge> remove(const std::string& name);

    /// nullptr when unknown.
    std::shared_ptr<TopicBridge> find(core::TopicId id) const;
    std::shared_ptr<TopicBridge> find(const std::string& name) const;
    /// Every bridge, by name.
    std::vector<std::shared_ptr<TopicBridge>> all() const;
    /// Bridges in the table now.
    std::size_t size() const;
    /// Waits until `name` is bridged; false on timeout.
    bool wait_for(const std::string& name, std::chrono::milliseconds timeout) const;

  private:
    mutable std::mutex mutex_;
    mutable std::condition_variable changed_;
    std::map<std::string, std::shared_ptr<TopicBridge>> by_name_;
    std::vector<std::shared_ptr<TopicBridge>> by_id_;  // nullptr where an id has no bridge
};

}  // namespace tgw::dds
