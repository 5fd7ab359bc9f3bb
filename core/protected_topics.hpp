// The non-preemptive rule's bookkeeping: which active topics a sample on the link must not cost their deadline.
#pragma once

#include <cstdint>
#include <limits>

#include "base/time.hpp"
#include "core/sample.hpp"

namespace tgw::core {

/// The two active topics with the least room (TTL less their own sample's last wire time), and their ranks: a
/// sample may hold the link at most the least room of the topics no less urgent than its own, itself aside. What
/// is more urgent goes first anyway; a topic without room (its own sample longer than its TTL) is not protected at
/// all. The Scheduler keeps it between releases and brings it up to date on push; it rebuilds it over all topics
/// only when one of the two goes inactive, the rate or a TTL changes. Two are kept, not all: a third, more urgent,
/// topic behind two less urgent ones with less room goes unprotected (less protection, never a stop).
/// docs/design.md §4.
class ProtectedTopics {
  public:
    static constexpr TopicId NONE = static_cast<TopicId>(-1);
    struct Guard {
        TopicId topic = NONE;
        base::Duration limit = base::Duration::max();  ///< its room
        std::int64_t rank = std::numeric_limits<std::int64_t>::max();
    };

    /// Considers a topic not yet among the two (a rebuild offers every active topic once).
    void offer(const Guard& guard);
    /// A topic's room changed. False if the two can no longer be told without a rebuild.
    bool update(const Guard& guard);
    /// The protected topic that bounds a sample of `candidate`, of `rank`; nullptr for none.
    const Guard* guard_for(TopicId candidate, std::int64_t rank) const {
        if (first_.topic != candidate && first_.rank <= rank)
            return &first_;
        if (second_.topic != candidate && second_.rank <= rank)
            return &second_;
        return nullptr;
    }
    /// How long a sample of `candidate`, of `rank`, may hold the link.
    base::Duration limit_for(TopicId candidate, std::int64_t rank) const {
        const Guard* guard = guard_for(candidate, rank);
        return guard == nullptr ? base::Duration::max() : guard->limit;
    }
    const Guard& first() const { return first_; }  ///< the least room
    const Guard& second() const { return second_; }

  private:
    Guard first_;
    Guard second_;
};

}  // namespace tgw::core
