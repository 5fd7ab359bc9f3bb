#include "gateway/dds/introduction_schedule.hpp"

#include <algorithm>

namespace tgw::dds {

void IntroductionSchedule::discovered(const Prefix& participant, base::SteadyTime now) {
    waiting_[participant] = Waiting{now, 0};
}

void IntroductionSchedule::answered(const Prefix& participant) {
    waiting_.erase(participant);
}

void IntroductionSchedule::removed(const Prefix& participant) {
    waiting_.erase(participant);
}

bool IntroductionSchedule::take_due(base::SteadyTime now) {
    bool due = false;
    for (auto it = waiting_.begin(); it != waiting_.end();) {
        Waiting& w = it->second;
        // One announcement reaches everyone at once: times that passed together count once.
        while (w.sent < AFTER.size() && w.discovered_at + AFTER[w.sent] <= now) {
            ++w.sent;
            due = true;
        }
        it = w.sent == AFTER.size() ? waiting_.erase(it) : std::next(it);
    }
    return due;
}

std::optional<base::SteadyTime> IntroductionSchedule::next_due() const {
    std::optional<base::SteadyTime> next;
    for (const auto& [participant, w] : waiting_) {
        const base::SteadyTime at = w.discovered_at + AFTER[w.sent];
        next = next ? std::min(*next, at) : at;
    }
    return next;
}

}  // namespace tgw::dds
