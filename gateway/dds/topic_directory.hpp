#pragma once

#include <mutex>
#include <string>
#include <vector>

#include "gateway/core/sample.hpp"

namespace tgw::dds {

/// Names of the bridged topics by TopicId, for the on-robot log. Thread-safe; entries are never removed.
class TopicDirectory {
  public:
    struct Names {
        std::string topic;
        std::string type_name;
    };

    void add(core::TopicId id, Names names) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (names_.size() <= id) {
            names_.resize(id + 1);
        }
        names_[id] = std::move(names);
    }

    /// Empty names for an unknown id.
    Names get(core::TopicId id) const {
        std::lock_guard<std::mutex> lock(mutex_);
        return id < names_.size() ? names_[id] : Names{};
    }

  private:
    mutable std::mutex mutex_;
    std::vector<Names> names_;
};

}  // namespace tgw::dds
