// Publishers discovered in Fast DDS's discovery thread, handed to the thread that creates entities for them.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <vector>

#include "passthrough/discovery.hpp"

namespace tgw::basecamp {

/// Entities must not be created in Fast DDS's callbacks: the discovery thread pushes, the owner's thread takes.
class DiscoveryQueue {
  public:
    /// For passthrough::Discovery: queues the publisher and wakes take().
    passthrough::Discovery::Callback callback() {
        return [this](passthrough::DiscoveredPublisher&& publisher) {
            {
                std::lock_guard<std::mutex> lock(mutex_);
                queued_.push_back(std::move(publisher));
            }
            wake_.notify_all();
        };
    }

    /// What was discovered since the last call, in order; waits up to `timeout` for the first.
    std::vector<passthrough::DiscoveredPublisher> take(std::chrono::milliseconds timeout) {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait_for(lock, timeout, [this] { return !queued_.empty(); });
        std::vector<passthrough::DiscoveredPublisher> out(std::make_move_iterator(queued_.begin()),
                                                          std::make_move_iterator(queued_.end()));
        queued_.clear();
        return out;
    }

  private:
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<passthrough::DiscoveredPublisher> queued_;
};

}  // namespace tgw::basecamp
