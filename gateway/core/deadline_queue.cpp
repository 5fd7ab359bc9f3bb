#include "gateway/core/deadline_queue.hpp"

#include <utility>

namespace tgw::core {

namespace {
std::int64_t ns_of(SteadyTime t) {
    return std::chrono::duration_cast<Duration>(t.time_since_epoch()).count();
}
}  // namespace

void DeadlineQueue::push(Sample&& sample, std::int64_t rank) {
    Slot slot;
    if (free_slots_.empty()) {
        slot = static_cast<Slot>(slots_.size());
        slots_.emplace_back();
    } else {
        slot = free_slots_.back();
        free_slots_.pop_back();
    }
    memory_bytes_ += sample.payload.size() + BOOKKEEPING_BYTES;
    slots_[slot] = Entry{std::move(sample), rank};
    by_urgency_.insert(urgency_key(slot));
    by_deadline_.insert(deadline_key(slot));
}

Sample DeadlineQueue::take(Slot slot) {
    by_urgency_.erase(urgency_key(slot));
    by_deadline_.erase(deadline_key(slot));
    Sample sample = std::move(slots_[slot].sample);
    slots_[slot].sample = Sample{};
    memory_bytes_ -= sample.payload.size() + BOOKKEEPING_BYTES;
    free_slots_.push_back(slot);
    return sample;
}

DeadlineQueue::UrgencyKey DeadlineQueue::urgency_key(Slot slot) const {
    const Entry& e = slots_[slot];
    return UrgencyKey{e.rank, ns_of(e.sample.deadline), e.sample.sequence, slot};
}

DeadlineQueue::DeadlineKey DeadlineQueue::deadline_key(Slot slot) const {
    const Sample& s = slots_[slot].sample;
    return DeadlineKey{ns_of(s.deadline), s.sequence, slot};
}

}  // namespace tgw::core
