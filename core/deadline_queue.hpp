#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <type_traits>
#include <vector>

#include "core/sample.hpp"

namespace tgw::core {

/// The prioritized message list: queued samples ordered by urgency (rank, then deadline, then arrival) and,
/// separately, by deadline for expiry. The rank is the policy's: the topic's TTL under `ttl` and `paper`, 0
/// under `edf`.
///
/// Samples of one topic nearly always arrive in deadline order, so each (topic, rank) keeps a lane: a FIFO of
/// slots sorted by deadline, appended at the back and, for the rare late sample, inserted in place. Three small
/// heaps over the lanes give the most urgent head, the earliest-deadline head and the least urgent tail. Push,
/// take of a head or tail, and the three queries cost O(log lanes); an out-of-order sample costs
/// O(log n + its distance from the nearer end of its lane); a take from the middle of a lane leaves a tombstone.
class DeadlineQueue {
  public:
    using Slot = std::uint32_t;

    /// What the scheduler reads of a queued sample without taking it.
    struct Peek {
        TopicId topic;
        base::SteadyTime deadline;
        std::size_t payload_bytes;
        std::uint64_t sequence;
        base::WallTime source_time;
        std::uint16_t route;
        bool keyed;
        /// The payload, valid until the queue changes: what a bundle's entry size depends on.
        const std::vector<std::uint8_t>* payload;
    };

  private:
    using LaneId = std::uint32_t;

    /// A queued sample, kept compact: the topic lives in the lane; times are stored as clock ticks.
    struct Record {
        std::vector<std::uint8_t> payload;
        std::array<std::uint8_t, 16> key_bytes{};
        base::SteadyTime::rep deadline = 0;
        base::SteadyTime::rep arrival = 0;
        base::WallTime::rep source_time = 0;
        std::uint64_t sequence = 0;
        union {
            Slot next_free;  ///< while the slot is free: the next free slot
            struct {
                std::uint16_t route;
                SampleKind kind;
            } output;  ///< while it holds a sample: Sample::route and Sample::kind
        };
        /// The lane in the low bits, flags in the top two.
        std::uint32_t lane_and_flags = 0;
    };

  public:
    /// Bookkeeping per queued sample beyond its payload, counted against the memory cap: the record and its
    /// slot in the lane. Per-lane costs (a few hundred bytes per topic) and the payload's own allocation
    /// overhead are not included.
    static constexpr std::size_t BOOKKEEPING_BYTES = sizeof(Record) + sizeof(Slot);

    /// Queues the sample; its slot holds it until it is taken (holds()).
    Slot push(Sample&& sample, std::int64_t rank);
    /// Whether `slot` still holds the sample of `sequence` push() put there: not taken since, whatever came after.
    bool holds(Slot slot, std::uint64_t sequence) const;

    bool empty() const { return size_ == 0; }
    std::size_t size() const { return size_; }
    /// Payload plus bookkeeping of everything queued.
    std::size_t memory_bytes() const { return memory_bytes_; }

    /// The ends of the order; the queue must not be empty, and for most_urgent() not all parked.
    Slot most_urgent() const;
    Slot least_urgent() const;
    Slot earliest_deadline() const;

    Peek at(Slot slot) const;
    /// The earliest deadline of `topic`'s queued samples (parked or not); nullopt when none is queued.
    std::optional<base::SteadyTime> earliest_deadline_of(TopicId topic) const;
    /// Remove the sample from the queue and hand it over.
    Sample take(Slot slot);

    /// A parked topic's samples stay queued (for expiry, eviction and the memory count) but are left out of
    /// most_urgent() and visit_by_urgency(): the gateway parks a topic while no base-camp reader matches it.
    void park(TopicId topic, bool parked);
    bool parked(TopicId topic) const { return topic < parked_.size() && parked_[topic]; }

    /// Call `visit(slot)` on queued samples in urgency order, most urgent first, until it returns false. The
    /// visitor may take() the slot it is given, and nothing else may change the queue meanwhile. Costs
    /// O(log visited) per sample visited.
    template <class Visit>
    void visit_by_urgency(Visit&& visit) {
        using V = std::remove_reference_t<Visit>;
        visit_by_urgency_impl(&visit,
                              [](void* v, Slot slot) { return static_cast<bool>((*static_cast<V*>(v))(slot)); });
    }

  private:
    static constexpr std::uint32_t LANE_MASK = 0x3fffffffu;
    static constexpr std::uint32_t KEY_VALID = 0x40000000u;
    static constexpr std::uint32_t DEAD = 0x80000000u;
    static constexpr std::size_t CHUNK_BITS = 12;
    static constexpr std::size_t CHUNK_SIZE = std::size_t{1} << CHUNK_BITS;
    static constexpr Slot NO_SLOT = 0xffffffffu;
    /// The sequence of a free slot's record: no sample's (Scheduler counts them up from 0).
    static constexpr std::uint64_t FREE_SEQUENCE = ~std::uint64_t{0};

    /// Order of samples: (rank, deadline, sequence), the lane breaking the remaining ties.
    struct Key {
        std::int64_t rank;
        base::SteadyTime::rep deadline;
        std::uint64_t sequence;
        LaneId lane;
        bool operator<(const Key& o) const {
            if (rank != o.rank)
                return rank < o.rank;
            if (deadline != o.deadline)
                return deadline < o.deadline;
            if (sequence != o.sequence)
                return sequence < o.sequence;
            return lane < o.lane;
        }
    };

    /// A binary heap over lanes with each lane's position kept, so a lane's key can change in O(log lanes).
    class LaneHeap {
      public:
        explicit LaneHeap(bool max_on_top) : max_on_top_(max_on_top) {}
        bool empty() const { return nodes_.empty(); }
        const Key& top() const { return nodes_.front(); }
        const std::vector<Key>& nodes() const { return nodes_; }
        /// Insert the lane or change its key.
        void set(const Key& key);
        void erase(LaneId lane);

      private:
        bool above(const Key& a, const Key& b) const { return max_on_top_ ? b < a : a < b; }
        void place(std::size_t i, const Key& key);
        void sift_up(std::size_t i);
        void sift_down(std::size_t i);

        bool max_on_top_;
        std::vector<Key> nodes_;
        std::vector<std::uint32_t> where_;  ///< per lane: its node, or NOWHERE
    };

    struct Lane {
        std::deque<Slot> slots;  ///< sorted by (deadline, sequence); taken ones stay as tombstones
        std::uint32_t tombstones = 0;
        TopicId topic = 0;
        std::int64_t rank = 0;
    };

    /// A place in the walk of visit_by_urgency: a lane's sample, and the head heap's node it came from.
    struct Cursor {
        Key key;
        std::uint32_t index;  ///< in the lane
        std::uint32_t heap_node;
    };

    using VisitFn = bool (*)(void*, Slot);
    void visit_by_urgency_impl(void* visitor, VisitFn fn);

    Record& record(Slot slot) { return chunks_[slot >> CHUNK_BITS][slot & (CHUNK_SIZE - 1)]; }
    const Record& record(Slot slot) const { return chunks_[slot >> CHUNK_BITS][slot & (CHUNK_SIZE - 1)]; }
    Slot allocate();
    void release_slot(Slot slot);
    LaneId lane_for(TopicId topic, std::int64_t rank);
    Key key_of(Slot slot) const;
    bool before(Slot a, Slot b) const;
    void insert_in_order(std::deque<Slot>& slots, Slot slot);
    /// Drop the tombstones at the lane's ends and bring the heaps up to date.
    void settle(LaneId lane);
    void compact(Lane& lane);

    std::vector<std::unique_ptr<Record[]>> chunks_;
    Slot free_head_ = NO_SLOT;
    Slot allocated_ = 0;
    std::vector<Lane> lanes_;
    std::vector<std::vector<LaneId>> lanes_of_topic_;
    std::vector<bool> parked_;  ///< per topic; its lanes are kept out of head_by_urgency_
    std::vector<LaneId> free_lanes_;
    LaneHeap head_by_urgency_{false};
    LaneHeap head_by_deadline_{false};  ///< keys with rank 0
    LaneHeap tail_by_urgency_{true};
    std::vector<Cursor> cursors_;
    std::vector<LaneId> touched_;
    bool visiting_ = false;
    std::size_t size_ = 0;
    std::size_t memory_bytes_ = 0;
};

}  // namespace tgw::core
