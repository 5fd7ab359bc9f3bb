#include "core/protected_topics.hpp"

namespace tgw::core {

void ProtectedTopics::offer(const Guard& guard) {
    if (guard.limit <= base::Duration::zero()) {
        return;  // no other sample's wait could let it arrive in time
    }
    if (guard.limit < first_.limit) {
        second_ = first_;
        first_ = guard;
    } else if (guard.limit < second_.limit) {
        second_ = guard;
    }
}

bool ProtectedTopics::update(const Guard& guard) {
    if (guard.limit <= base::Duration::zero()) {
        return guard.topic != first_.topic && guard.topic != second_.topic;  // one leaves: the next is unknown
    }
    if (guard.topic == first_.topic) {
        if (guard.limit > second_.limit)
            return false;  // the new second is unknown
        first_ = guard;
    } else if (guard.topic == second_.topic) {
        if (guard.limit < first_.limit) {
            second_ = first_;
            first_ = guard;
        } else if (guard.limit <= second_.limit) {
            second_ = guard;
        } else {
            return false;
        }
    } else {
        offer(guard);
    }
    return true;
}

}  // namespace tgw::core
