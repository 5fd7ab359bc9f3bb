#pragma once

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/sample_sink.hpp"

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
        const bool refused = refuses_nts();
        if (refused) {
            dropped_.push_back(Dropped{std::move(sample), core::DropReason::write_failed});
        } else {
            depart("sample " + std::to_string(sample.topic));
            forwarded_.push_back(std::move(sample));
        }
        changed_.notify_all();
        return !refused;
    }
    void send_repair(std::uint64_t id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        depart("repair " + std::to_string(id));
        changed_.notify_all();
    }
    void discard_repair(std::uint64_t id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        discarded_repairs_.push_back(id);
        changed_.notify_all();
    }
    void sample_cut_short(std::uint64_t sample, core::DropReason reason) override {
        std::lock_guard<std::mutex> lock(mutex_);
        cut_short_.emplace_back(sample, reason);
        changed_.notify_all();
    }
    /// The samples cut short (SampleSink::sample_cut_short), in order.
    std::vector<std::pair<std::uint64_t, core::DropReason>> cut_short() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return cut_short_;
    }
    /// What left for the link, in order: "sample TOPIC_ID" for a sample sent alone, "bundle", "repair ID".
    std::vector<std::string> departures() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return departures_;
    }
    /// Waits until at least `n` departures (departures()) or `timeout` passed; true if they came.
    bool wait_for_departures(std::size_t n, std::chrono::milliseconds timeout) const {
        std::unique_lock<std::mutex> lock(mutex_);
        return changed_.wait_for(lock, timeout, [&] { return departures_.size() >= n; });
    }
    /// The thread that wrote each departure (departures()), in order.
    std::vector<std::thread::id> departure_threads() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return departure_threads_;
    }
    std::vector<std::uint64_t> discarded_repairs() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return discarded_repairs_;
    }
    /// Keeps the samples as forwarded (or refused) one by one, and the bundle's topics and wire size.
    std::size_t forward_bundle(std::vector<core::Sample>&& samples, std::size_t wire_bytes) override {
        std::lock_guard<std::mutex> lock(mutex_);
        const bool refused = refuses_nts();
        Bundle bundle{{}, wire_bytes};
        for (core::Sample& sample : samples) {
            bundle.topics.push_back(sample.topic);
            if (refused) {
                if (!sample.chunk)  // the scheduler logs a chunked sample whole
                    dropped_.push_back(Dropped{std::move(sample), core::DropReason::write_failed});
            } else {
                forwarded_.push_back(std::move(sample));
            }
        }
        if (!refused)
            depart("bundle");
        bundles_.push_back(std::move(bundle));
        changed_.notify_all();
        return refused ? 0 : wire_bytes;
    }
    /// From now on, after `after` more writes (forwards or bundles) that pass, the next `count` (all of them by
    /// default) fail as a refused WAN write does.
    void refuse_writes(std::size_t count = ALL, std::size_t after = 0) {
        std::lock_guard<std::mutex> lock(mutex_);
        passes_left_ = after;
        refusals_left_ = count;
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
    void depart(std::string what) {  // mutex_ held
        departures_.push_back(std::move(what));
        departure_threads_.push_back(std::this_thread::get_id());
    }
    static constexpr std::size_t ALL = SIZE_MAX;
    bool refuses_nts() {
        if (passes_left_ > 0) {
            --passes_left_;
            return false;
        }
        if (refusals_left_ == 0) {
            return false;
        }
        if (refusals_left_ != ALL) {
            --refusals_left_;
        }
        return true;
    }

    mutable std::mutex mutex_;
    mutable std::condition_variable changed_;
    std::vector<core::Sample> forwarded_;
    std::vector<Dropped> dropped_;
    std::vector<Bundle> bundles_;
    std::vector<std::string> departures_;
    std::vector<std::uint64_t> discarded_repairs_;
    std::vector<std::pair<std::uint64_t, core::DropReason>> cut_short_;
    std::vector<std::thread::id> departure_threads_;
    std::size_t passes_left_ = 0;
    std::size_t refusals_left_ = 0;
};

}  // namespace tgw::test
