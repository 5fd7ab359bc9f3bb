#include "core/deadline_queue.hpp"

#include <algorithm>
#include <utility>

namespace tgw::core {

namespace {
constexpr std::uint32_t NOWHERE = 0xffffffffu;
}  // namespace

// ---- LaneHeap ----

void DeadlineQueue::LaneHeap::place(std::size_t i, const Key& key) {
    nodes_[i] = key;
    where_[key.lane] = static_cast<std::uint32_t>(i);
}

void DeadlineQueue::LaneHeap::sift_up(std::size_t i) {
    const Key key = nodes_[i];
    while (i > 0) {
        const std::size_t parent = (i - 1) / 2;
        if (!above(key, nodes_[parent]))
            break;
        place(i, nodes_[parent]);
        i = parent;
    }
    place(i, key);
}

void DeadlineQueue::LaneHeap::sift_down(std::size_t i) {
    const Key key = nodes_[i];
    const std::size_t n = nodes_.size();
    for (;;) {
        std::size_t child = 2 * i + 1;
        if (child >= n)
            break;
        if (child + 1 < n && above(nodes_[child + 1], nodes_[child]))
            ++child;
        if (!above(nodes_[child], key))
            break;
        place(i, nodes_[child]);
        i = child;
    }
    place(i, key);
}

void DeadlineQueue::LaneHeap::set(const Key& key) {
    if (key.lane >= where_.size())
        where_.resize(key.lane + 1, NOWHERE);
    const std::uint32_t i = where_[key.lane];
    if (i == NOWHERE) {
        nodes_.push_back(key);
        sift_up(nodes_.size() - 1);
        return;
    }
    const Key old = nodes_[i];
    nodes_[i] = key;
    if (above(key, old))
        sift_up(i);
    else
        sift_down(i);
}

void DeadlineQueue::LaneHeap::erase(LaneId lane) {
    if (lane >= where_.size() || where_[lane] == NOWHERE)
        return;
    const std::size_t i = where_[lane];
    where_[lane] = NOWHERE;
    const Key last = nodes_.back();
    nodes_.pop_back();
    if (i < nodes_.size()) {
        place(i, last);
        sift_up(i);
        sift_down(where_[last.lane]);
    }
}

// ---- slots and lanes ----

DeadlineQueue::Slot DeadlineQueue::allocate() {
    if (free_head_ != NO_SLOT) {
        const Slot slot = free_head_;
        free_head_ = record(slot).next_free;
        return slot;
    }
    if (allocated_ == chunks_.size() * CHUNK_SIZE)
        chunks_.push_back(std::make_unique<Record[]>(CHUNK_SIZE));
    return allocated_++;
}

void DeadlineQueue::release_slot(Slot slot) {
    Record& r = record(slot);
    r.payload = {};
    r.lane_and_flags = 0;
    r.sequence = FREE_SEQUENCE;
    r.next_free = free_head_;
    free_head_ = slot;
}

DeadlineQueue::LaneId DeadlineQueue::lane_for(TopicId topic, std::int64_t rank) {
    if (topic >= lanes_of_topic_.size())
        lanes_of_topic_.resize(static_cast<std::size_t>(topic) + 1);
    for (LaneId id : lanes_of_topic_[topic]) {
        if (lanes_[id].rank == rank)
            return id;
    }
    LaneId id;
    if (!free_lanes_.empty()) {
        id = free_lanes_.back();
        free_lanes_.pop_back();
    } else {
        id = static_cast<LaneId>(lanes_.size());
        lanes_.emplace_back();
    }
    Lane& lane = lanes_[id];
    lane.tombstones = 0;
    lane.topic = topic;
    lane.rank = rank;
    lanes_of_topic_[topic].push_back(id);
    return id;
}

DeadlineQueue::Key DeadlineQueue::key_of(Slot slot) const {
    const Record& r = record(slot);
    const LaneId lane = r.lane_and_flags & LANE_MASK;
    return Key{lanes_[lane].rank, r.deadline, r.sequence, lane};
}

bool DeadlineQueue::before(Slot a, Slot b) const {
    const Record& ra = record(a);
    const Record& rb = record(b);
    if (ra.deadline != rb.deadline)
        return ra.deadline < rb.deadline;
    return ra.sequence < rb.sequence;
}

// ---- operations ----

bool DeadlineQueue::holds(Slot slot, std::uint64_t sequence) const {
    if (slot >= allocated_)
        return false;
    const Record& r = record(slot);
    return r.sequence == sequence && (r.lane_and_flags & DEAD) == 0;
}

DeadlineQueue::Slot DeadlineQueue::push(Sample&& sample, std::int64_t rank) {
    const LaneId lane_id = lane_for(sample.topic, rank);
    const Slot slot = allocate();
    Record& r = record(slot);
    r.payload = std::move(sample.payload);
    r.key_bytes = sample.key.bytes;
    r.deadline = sample.deadline.time_since_epoch().count();
    r.arrival = sample.arrival.time_since_epoch().count();
    r.source_time = sample.source_time.time_since_epoch().count();
    r.sequence = sample.sequence;
    r.output.route = sample.route;
    r.output.kind = sample.kind;
    r.lane_and_flags = lane_id | (sample.key.valid ? KEY_VALID : 0u);
    memory_bytes_ += r.payload.size() + BOOKKEEPING_BYTES;
    ++size_;

    Lane& lane = lanes_[lane_id];
    const bool was_empty = lane.slots.empty();
    if (was_empty || !before(slot, lane.slots.back())) {
        lane.slots.push_back(slot);
        tail_by_urgency_.set(key_of(slot));
    } else {
        insert_in_order(lane.slots, slot);
    }
    if (lane.slots.front() == slot) {
        const Key key = key_of(slot);
        if (!parked(lane.topic))
            head_by_urgency_.set(key);
        head_by_deadline_.set(Key{0, key.deadline, key.sequence, lane_id});
    }
    return slot;
}

void DeadlineQueue::park(TopicId topic, bool parked) {
    if (topic >= parked_.size())
        parked_.resize(static_cast<std::size_t>(topic) + 1, false);
    parked_[topic] = parked;
    if (topic >= lanes_of_topic_.size())
        return;
    for (LaneId lane : lanes_of_topic_[topic]) {
        if (parked)
            head_by_urgency_.erase(lane);
        else if (!lanes_[lane].slots.empty())
            head_by_urgency_.set(key_of(lanes_[lane].slots.front()));
    }
}

void DeadlineQueue::insert_in_order(std::deque<Slot>& slots, Slot slot) {
    // Late samples are usually late by little: gallop back from the tail, then bisect.
    const auto n = static_cast<std::int64_t>(slots.size());
    std::int64_t hi = n - 1;  // slots[hi] comes after the new sample
    std::int64_t lo = -1;     // slots[lo] does not, or lo is before the front
    for (std::int64_t step = 1;; step *= 2) {
        const std::int64_t probe = hi - step;
        if (probe < 0)
            break;
        if (!before(slot, slots[static_cast<std::size_t>(probe)])) {
            lo = probe;
            break;
        }
        hi = probe;
    }
    while (hi - lo > 1) {
        const std::int64_t mid = lo + (hi - lo) / 2;
        if (before(slot, slots[static_cast<std::size_t>(mid)]))
            hi = mid;
        else
            lo = mid;
    }
    // deque::insert shifts the shorter side.
    slots.insert(slots.begin() + static_cast<std::ptrdiff_t>(hi), slot);
}

DeadlineQueue::Slot DeadlineQueue::most_urgent() const {
    return lanes_[head_by_urgency_.top().lane].slots.front();
}

DeadlineQueue::Slot DeadlineQueue::least_urgent() const {
    return lanes_[tail_by_urgency_.top().lane].slots.back();
}

DeadlineQueue::Slot DeadlineQueue::earliest_deadline() const {
    return lanes_[head_by_deadline_.top().lane].slots.front();
}

DeadlineQueue::Peek DeadlineQueue::at(Slot slot) const {
    const Record& r = record(slot);
    return Peek{lanes_[r.lane_and_flags & LANE_MASK].topic,
                base::SteadyTime(base::SteadyTime::duration(r.deadline)),
                r.payload.size(),
                r.sequence,
                base::WallTime(base::WallTime::duration(r.source_time)),
                r.output.route,
                (r.lane_and_flags & KEY_VALID) != 0,
                &r.payload};
}

std::optional<base::SteadyTime> DeadlineQueue::earliest_deadline_of(TopicId topic) const {
    if (topic >= lanes_of_topic_.size()) {
        return std::nullopt;
    }
    std::optional<base::SteadyTime::rep> earliest;
    for (const LaneId id : lanes_of_topic_[topic]) {
        // A lane is sorted by deadline, and its ends are never tombstones outside a visit.
        for (const Slot slot : lanes_[id].slots) {
            const Record& r = record(slot);
            if ((r.lane_and_flags & DEAD) == 0) {
                earliest = earliest ? std::min(*earliest, r.deadline) : r.deadline;
                break;
            }
        }
    }
    if (!earliest) {
        return std::nullopt;
    }
    return base::SteadyTime(base::SteadyTime::duration(*earliest));
}

Sample DeadlineQueue::take(Slot slot) {
    Record& r = record(slot);
    const LaneId lane_id = r.lane_and_flags & LANE_MASK;
    Sample sample;
    sample.topic = lanes_[lane_id].topic;
    sample.payload = std::move(r.payload);
    r.payload = {};
    sample.key.bytes = r.key_bytes;
    sample.key.valid = (r.lane_and_flags & KEY_VALID) != 0;
    sample.source_time = base::WallTime(base::WallTime::duration(r.source_time));
    sample.arrival = base::SteadyTime(base::SteadyTime::duration(r.arrival));
    sample.deadline = base::SteadyTime(base::SteadyTime::duration(r.deadline));
    sample.sequence = r.sequence;
    sample.route = r.output.route;
    sample.kind = r.output.kind;
    memory_bytes_ -= sample.payload.size() + BOOKKEEPING_BYTES;
    --size_;

    // The slot stays in its lane as a tombstone until it reaches an end or the lane is compacted.
    r.lane_and_flags |= DEAD;
    ++lanes_[lane_id].tombstones;
    if (visiting_)
        touched_.push_back(lane_id);
    else
        settle(lane_id);
    return sample;
}

void DeadlineQueue::settle(LaneId lane_id) {
    Lane& lane = lanes_[lane_id];
    std::deque<Slot>& slots = lane.slots;
    bool new_head = false;
    bool new_tail = false;
    while (!slots.empty() && (record(slots.front()).lane_and_flags & DEAD) != 0) {
        release_slot(slots.front());
        slots.pop_front();
        --lane.tombstones;
        new_head = true;
    }
    while (!slots.empty() && (record(slots.back()).lane_and_flags & DEAD) != 0) {
        release_slot(slots.back());
        slots.pop_back();
        --lane.tombstones;
        new_tail = true;
    }
    if (slots.empty()) {
        head_by_urgency_.erase(lane_id);
        head_by_deadline_.erase(lane_id);
        tail_by_urgency_.erase(lane_id);
        // Keep one lane per topic for reuse; lanes of a rank the topic no longer has are recycled.
        std::vector<LaneId>& of_topic = lanes_of_topic_[lane.topic];
        const auto it = std::find(of_topic.begin(), of_topic.end(), lane_id);
        if (of_topic.size() > 1 && it != of_topic.end()) {
            of_topic.erase(it);
            free_lanes_.push_back(lane_id);
        }
        return;
    }
    if (lane.tombstones > 64 && 2 * static_cast<std::size_t>(lane.tombstones) > slots.size())
        compact(lane);  // keeps both ends
    if (new_head) {
        const Key head = key_of(slots.front());
        if (!parked(lane.topic))
            head_by_urgency_.set(head);
        head_by_deadline_.set(Key{0, head.deadline, head.sequence, lane_id});
    }
    if (new_tail)
        tail_by_urgency_.set(key_of(slots.back()));
}

void DeadlineQueue::compact(Lane& lane) {
    std::deque<Slot>& slots = lane.slots;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < slots.size(); ++i) {
        const Slot slot = slots[i];
        if ((record(slot).lane_and_flags & DEAD) != 0) {
            release_slot(slot);
            continue;
        }
        slots[kept++] = slot;
    }
    slots.resize(kept);
    lane.tombstones = 0;
}

void DeadlineQueue::visit_by_urgency_impl(void* visitor, VisitFn fn) {
    if (head_by_urgency_.empty())
        return;
    // A lazy merge of the lanes: the heads enter the walk in the order of the head heap (a node's children
    // after the node), a lane's next sample after the one before it. Takes are only marked until the end, so
    // the heap and the lanes hold still meanwhile.
    visiting_ = true;
    cursors_.clear();
    const auto later = [](const Cursor& a, const Cursor& b) { return b.key < a.key; };
    const std::vector<Key>& heads = head_by_urgency_.nodes();
    const auto enter_head = [&](std::size_t node) {
        if (node < heads.size()) {
            const Key& key = heads[node];
            cursors_.push_back(Cursor{key, 0, static_cast<std::uint32_t>(node)});
            std::push_heap(cursors_.begin(), cursors_.end(), later);
        }
    };
    enter_head(0);
    while (!cursors_.empty()) {
        std::pop_heap(cursors_.begin(), cursors_.end(), later);
        const Cursor cursor = cursors_.back();
        cursors_.pop_back();
        const Lane& lane = lanes_[cursor.key.lane];
        // Nothing moves in the lanes or the heap while visiting, so what comes next can be found afterwards.
        if (!fn(visitor, lane.slots[cursor.index]))
            break;
        if (cursor.heap_node != NOWHERE) {
            enter_head(2 * static_cast<std::size_t>(cursor.heap_node) + 1);
            enter_head(2 * static_cast<std::size_t>(cursor.heap_node) + 2);
        }
        for (std::size_t j = cursor.index + 1; j < lane.slots.size(); ++j) {
            const Slot next = lane.slots[j];
            if ((record(next).lane_and_flags & DEAD) == 0) {
                cursors_.push_back(Cursor{key_of(next), static_cast<std::uint32_t>(j), NOWHERE});
                std::push_heap(cursors_.begin(), cursors_.end(), later);
                break;
            }
        }
    }
    visiting_ = false;
    std::sort(touched_.begin(), touched_.end());
    touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());
    for (LaneId lane : touched_)
        settle(lane);
    touched_.clear();
}

}  // namespace tgw::core
