#pragma once

#include <cstddef>
#include <cstdint>
#include <set>
#include <vector>

#include "gateway/core/sample.hpp"

namespace tgw::core {

/// The prioritized message list: queued samples ordered by urgency (rank, then deadline, then arrival) and,
/// separately, by deadline for expiry. Insert, take, and access to both ends are O(log n). The rank is the
/// policy's: the topic's TTL under `ttl` and `paper`, 0 under `edf`.
class DeadlineQueue {
  public:
    using Slot = std::uint32_t;

    struct UrgencyKey {
        std::int64_t rank;
        std::int64_t deadline_ns;
        std::uint64_t sequence;
        Slot slot;
        bool operator<(const UrgencyKey& o) const {
            if (rank != o.rank)
                return rank < o.rank;
            if (deadline_ns != o.deadline_ns)
                return deadline_ns < o.deadline_ns;
            return sequence < o.sequence;
        }
    };

    /// Estimated bookkeeping per queued sample beyond its payload, counted against the memory cap.
    static constexpr std::size_t BOOKKEEPING_BYTES = sizeof(Sample) + 2 * 64;

    void push(Sample&& sample, std::int64_t rank);

    bool empty() const { return by_urgency_.empty(); }
    std::size_t size() const { return by_urgency_.size(); }
    /// Payload plus bookkeeping of everything queued.
    std::size_t memory_bytes() const { return memory_bytes_; }

    /// Samples in urgency order, most urgent first.
    const std::set<UrgencyKey>& by_urgency() const { return by_urgency_; }
    Slot most_urgent() const { return by_urgency_.begin()->slot; }
    Slot least_urgent() const { return by_urgency_.rbegin()->slot; }
    Slot earliest_deadline() const { return by_deadline_.begin()->slot; }

    const Sample& at(Slot slot) const { return slots_[slot].sample; }
    /// Remove the sample from the queue and hand it over.
    Sample take(Slot slot);

  private:
    struct DeadlineKey {
        std::int64_t deadline_ns;
        std::uint64_t sequence;
        Slot slot;
        bool operator<(const DeadlineKey& o) const {
            if (deadline_ns != o.deadline_ns)
                return deadline_ns < o.deadline_ns;
            return sequence < o.sequence;
        }
    };
    struct Entry {
        Sample sample;
        std::int64_t rank = 0;
    };

    UrgencyKey urgency_key(Slot slot) const;
    DeadlineKey deadline_key(Slot slot) const;

    std::vector<Entry> slots_;
    std::vector<Slot> free_slots_;
    std::set<UrgencyKey> by_urgency_;
    std::set<DeadlineKey> by_deadline_;
    std::size_t memory_bytes_ = 0;
};

}  // namespace tgw::core
