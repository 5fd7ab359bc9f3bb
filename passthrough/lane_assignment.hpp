#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <shared_mutex>

#include <fastdds/rtps/common/Guid.h>
#include <fastdds/rtps/common/InstanceHandle.h>

namespace tgw::passthrough {

/// Which lane of a topic carries each robot-domain writer. A writer whose QoS meets several of the topic's
/// readers (a reliable writer also matches the best-effort lane's reader) reaches each of them, but only its
/// own lane forwards it, so nothing crosses twice. Thread-safe: the bridge threads ask, the gateway's worker
/// assigns.
class LaneAssignment {
  public:
    void assign(const eprosima::fastrtps::rtps::GUID_t& writer, std::uint16_t lane) {
        std::unique_lock<std::shared_mutex> lock(mutex_);
        lanes_[eprosima::fastrtps::rtps::InstanceHandle_t(writer)] = lane;
        if (lane != 0) {
            several_lanes_.store(true, std::memory_order_release);
        }
    }

    /// The topic has a second lane, which may have no writer of its own (a lane the --qos file declared after a
    /// publisher had its own): from now on each lane forwards only its own writers. Before this was told, a
    /// restarted gateway whose publishers ran already forwarded each of their samples twice, through their lane
    /// and the declared one (a fleet on the testbed: 186 samples of each topic received for 93 published).
    void several_lanes() { several_lanes_.store(true, std::memory_order_release); }

    /// Forgets a writer that left; the lane that carried it, if it was assigned.
    std::optional<std::uint16_t> release(const eprosima::fastrtps::rtps::GUID_t& writer) {
        std::unique_lock<std::shared_mutex> lock(mutex_);
        const auto it = lanes_.find(eprosima::fastrtps::rtps::InstanceHandle_t(writer));
        if (it == lanes_.end()) {
            return std::nullopt;
        }
        const std::uint16_t lane = it->second;
        lanes_.erase(it);
        return lane;
    }

    /// Writers assigned to `lane` now.
    std::size_t writers_on(std::uint16_t lane) const {
        std::shared_lock<std::shared_mutex> lock(mutex_);
        return static_cast<std::size_t>(
            std::count_if(lanes_.begin(), lanes_.end(), [lane](const auto& entry) { return entry.second == lane; }));
    }

    /// True when `lane` forwards the samples of the writer `publication` (SampleInfo::publication_handle). A
    /// writer not assigned yet goes through whichever lane has it: its own lane does not exist yet.
    bool carries(const eprosima::fastrtps::rtps::InstanceHandle_t& publication, std::uint16_t lane) const {
        // The usual topic has one lane: every sample takes it, without a lookup on the per-sample path.
        if (!several_lanes_.load(std::memory_order_acquire)) {
            return true;
        }
        std::shared_lock<std::shared_mutex> lock(mutex_);
        const auto it = lanes_.find(publication);
        return it == lanes_.end() || it->second == lane;
    }

  private:
    mutable std::shared_mutex mutex_;
    std::map<eprosima::fastrtps::rtps::InstanceHandle_t, std::uint16_t> lanes_;
    std::atomic<bool> several_lanes_{false};
};

}  // namespace tgw::passthrough
