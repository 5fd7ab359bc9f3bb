#include "gateway/sim/rate_profile.hpp"

#include <algorithm>

namespace tgw::sim {

using base::Duration;

Duration RateProfile::finish_offset(Duration offset, std::uint64_t bits) const {
    double remaining = static_cast<double>(bits);
    Duration t = offset;
    for (std::size_t i = step_index(offset);; ++i) {
        const double rate = steps()[i].rate_bps;
        const Duration step_end = i + 1 < steps().size() ? steps()[i + 1].at : Duration::max();
        if (rate > 0.0) {
            const Duration needed = base::from_seconds(remaining / rate);
            if (step_end == Duration::max() || t + needed <= step_end) {
                return t + needed;
            }
            remaining -= rate * base::to_seconds(step_end - t);
        } else if (step_end == Duration::max()) {
            return Duration::max();
        }
        t = std::max(t, step_end);
    }
}

double RateProfile::capacity_bits(Duration from, Duration to) const {
    double bits = 0.0;
    for (Duration t = from; t < to;) {
        const Duration step_end = std::min(to, next_change_after(t));
        bits += rate_at(t) * base::to_seconds(step_end - t);
        t = step_end;
    }
    return bits;
}

}  // namespace tgw::sim
