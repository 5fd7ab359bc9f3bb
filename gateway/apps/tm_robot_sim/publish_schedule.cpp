#include "gateway/apps/tm_robot_sim/publish_schedule.hpp"

namespace tgw::robot_sim {

PublishSchedule::PublishSchedule(base::SteadyTime start, const std::vector<double>& rates_hz) : start_(start) {
    const auto n = rates_hz.size();
    for (std::size_t i = 0; i < n; ++i) {
        const base::Duration period = base::from_seconds(1.0 / rates_hz[i]);
        periods_.push_back(period);
        phases_.push_back(period * static_cast<base::Duration::rep>(i) / static_cast<base::Duration::rep>(n));
        counts_.push_back(0);
    }
}

base::SteadyTime PublishSchedule::due_at(std::size_t stream) const {
    return start_ + phases_[stream] + periods_[stream] * counts_[stream];
}

PublishSchedule::Due PublishSchedule::next() const {
    Due due;
    for (std::size_t i = 0; i < periods_.size(); ++i) {
        const auto at = due_at(i);
        if (i == 0 || at < due.at)
            due = Due{i, at, counts_[i]};
    }
    return due;
}

void PublishSchedule::advance() {
    ++counts_[next().stream];
}

}  // namespace tgw::robot_sim
