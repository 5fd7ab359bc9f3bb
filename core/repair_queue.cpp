#include "core/repair_queue.hpp"

#include <algorithm>
#include <tuple>

namespace tgw::core {

bool RepairQueue::Entry::operator<(const Entry& other) const {
    return std::tie(rank, repair.deadline, sequence) < std::tie(other.rank, other.repair.deadline, other.sequence);
}

void RepairQueue::push(const Repair& repair, std::int64_t rank) {
    entries_.insert(Entry{rank, repair, next_sequence_++});
}

Repair RepairQueue::take(Iterator it) {
    const Repair repair = it->repair;
    entries_.erase(it);
    return repair;
}

std::optional<base::SteadyTime> RepairQueue::earliest_deadline() const {
    if (entries_.empty()) {
        return std::nullopt;
    }
    return std::min_element(entries_.begin(), entries_.end(),
                            [](const Entry& a, const Entry& b) { return a.repair.deadline < b.repair.deadline; })
        ->repair.deadline;
}

}  // namespace tgw::core
