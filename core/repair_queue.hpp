// The repairs waiting for the link, in the scheduler's order of urgency.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <set>

#include "core/repair.hpp"

namespace tgw::core {

/// Repairs ordered as the DeadlineQueue orders samples: (rank, deadline), then the order they came in. They are
/// few (what reliable readers asked for and the link has not yet carried), so an ordered set serves.
class RepairQueue {
  public:
    struct Entry {
        std::int64_t rank = 0;
        Repair repair;
        std::uint64_t sequence = 0;
        bool operator<(const Entry& other) const;
    };
    using Iterator = std::set<Entry>::const_iterator;

    void push(const Repair& repair, std::int64_t rank);
    bool empty() const { return entries_.empty(); }
    std::size_t size() const { return entries_.size(); }
    Iterator begin() const { return entries_.begin(); }
    Iterator end() const { return entries_.end(); }
    /// Removes the entry and returns its repair.
    Repair take(Iterator it);
    /// The least urgent, for a queue over its bound.
    Iterator least_urgent() const { return std::prev(entries_.end()); }
    /// The earliest deadline of any queued repair; nullopt when empty. Linear: the queue is short.
    std::optional<base::SteadyTime> earliest_deadline() const;

  private:
    std::set<Entry> entries_;
    std::uint64_t next_sequence_ = 0;
};

}  // namespace tgw::core
