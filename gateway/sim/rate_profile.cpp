#include "gateway/sim/rate_profile.hpp"

#include <algorithm>
#include <utility>

namespace tgw::sim {

using core::Duration;

RateProfile::RateProfile(std::vector<Step> steps) : steps_(std::move(steps)) {}

std::size_t RateProfile::step_index(Duration offset) const {
    auto it =
        std::upper_bound(steps_.begin(), steps_.end(), offset, [](Duration t, const Step& s) { return t < s.at; });
    return it == steps_.begin() ? 0 : static_cast<std::size_t>(it - steps_.begin() - 1);
}

double RateProfile::rate_at(Duration offset) const {
    return steps_[step_index(offset)].rate_bps;
}

Duration RateProfile::next_change_after(Duration offset) const {
    auto it =
        std::upper_bound(steps_.begin(), steps_.end(), offset, [](Duration t, const Step& s) { return t < s.at; });
    return it == steps_.end() ? Duration::max() : it->at;
}

Duration RateProfile::finish_offset(Duration offset, std::uint64_t bits) const {
    double remaining = static_cast<double>(bits);
    Duration t = offset;
    for (std::size_t i = step_index(offset);; ++i) {
        const double rate = steps_[i].rate_bps;
        const Duration step_end = i + 1 < steps_.size() ? steps_[i + 1].at : Duration::max();
        if (rate > 0.0) {
            const Duration needed = core::from_seconds(remaining / rate);
            if (step_end == Duration::max() || t + needed <= step_end) {
                return t + needed;
            }
            remaining -= rate * core::to_seconds(step_end - t);
        } else if (step_end == Duration::max()) {
            return Duration::max();
        }
        t = std::max(t, step_end);
    }
}

}  // namespace tgw::sim
