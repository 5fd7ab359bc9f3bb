#pragma once

#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "gateway/core/sample.hpp"
#include "gateway/dds/topic_bridge.hpp"

namespace tgw::dds {

/// The gateway's bridged topics, found by name (discovery) or by TopicId (a sample's way out, the on-robot log).
/// A bridge, once added, lives as long as the table, so the pointers handed out stay valid. Thread-safe.
class TopicTable {
  public:
    /// `bridge`'s name and id must be new.
    void add(std::unique_ptr<TopicBridge> bridge);

    /// nullptr when unknown.
    TopicBridge* find(core::TopicId id) const;
    TopicBridge* find(const std::string& name) const;
    /// Every bridge, by name.
    std::vector<TopicBridge*> all() const;
    /// Waits until `name` is bridged; false on timeout.
    bool wait_for(const std::string& name, std::chrono::milliseconds timeout) const;

  private:
    mutable std::mutex mutex_;
    mutable std::condition_variable changed_;
    std::map<std::string, std::unique_ptr<TopicBridge>> by_name_;
    std::vector<TopicBridge*> by_id_;  // nullptr where an id has no bridge (its first lane was refused)
};

}  // namespace tgw::dds
