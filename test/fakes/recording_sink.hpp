#pragma once

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "gateway/core/sample_sink.hpp"

namespace tgw::test {

/// Keeps every decision of the scheduler, in order. Thread-safe, with waits for tests of threaded code.
class RecordingSink final : public core::SampleSink {
  public:
    struct Bundle {
        std::vector<core::TopicId> topics;
        std::size_t wire_bytes;
    };
    struct Dropped {
        core::Sample sample;
        core::DropReason reason;
    };

    bool forward(core::Sample&& sample) override {
        std::lock_guard<std::mutex> lock(mutex_);
        if (refuse_writes_) {
            dropped_.push_back(Dropped{std::move(sample), core::DropReason::write_failed});
        } else {
            forwarded_.push_back(std::move(sample));
        }
        changed_.notify_all();
        return !refuse_writes_;
    }
    /// Keeps the samples as forwarded (or refused) one by one, and the bundle's topics and wire size.
    std::size_t forward_bundle(std::vector<core::Sample>&& samples, std::size_t wire_bytes) override {
        std::lock_guard<std::mutex> lock(mutex_);
        Bundle bundle{{}, wire_bytes};
        for (core::Sample& sample : samples) {
            bundle.topics.push_back(sample.topic);
            if (refuse_writes_) {
                if (!sample.chunk)  // the scheduler logs a chunked sample whole
                    dropped_.push_back(Dropped{std::move(sample), core::DropReason::write_failed});
            } else {
                forwarded_.push_back(std::move(sample));
            }
        }
        bundles_.push_back(std::move(bundle));
        changed_.notify_all();
        return refuse_writes_ ? 0 : wire_bytes;
    }
    /// From now on, every forward fails as a refused WAN write does.
    void refuse_writes() {
        std::lock_guard<std::mutex> lock(mutex_);
        refuse_writes_ = true;
    }
    void drop(core::Sample&& sample, core::DropReason reason) override {
        std::lock_guard<std::mutex> lock(mutex_);
        dropped_.push_back(Dropped{std::move(sample), reason});
        changed_.notify_all();
    }

    std::vector<core::Sample> forwarded() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return forwarded_;
    }
    std::vector<Dropped> dropped() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return dropped_;
    }
    std::vector<Bundle> bundles() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return bundles_;
    }
    /// Topics of the forwarded samples, in order.
    std::vector<core::TopicId> forwarded_topics() const {
        std::lock_guard<std::mutex> lock(mutex_);
        std::vector<core::TopicId> topics;
        for (const auto& s : forwarded_)
            topics.push_back(s.topic);
        return topics;
    }
    std::size_t dropped_count(core::DropReason reason) const {
        std::lock_guard<std::mutex> lock(mutex_);
        return static_cast<std::size_t>(
            std::count_if(dropped_.begin(), dropped_.end(), [&](const Dropped& d) { return d.reason == reason; }));
    }
    /// Waits until at least `n` samples were forwarded or `timeout` passed; true if they were.
    bool wait_for_forwarded(std::size_t n, std::chrono::milliseconds timeout) const {
        std::unique_lock<std::mutex> lock(mutex_);
        return changed_.wait_for(lock, timeout, [&] { return forwarded_.size() >= n; });
    }

  private:
    mutable std::mutex mutex_;
    mutable std::condition_variable changed_;
    std::vector<core::Sample> forwarded_;
    std::vector<Dropped> dropped_;
    std::vector<Bundle> bundles_;
    bool refuse_writes_ = false;
};

}  // namespace tgw::test
