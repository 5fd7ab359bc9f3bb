#include "core/rate_cap.hpp"

#include <algorithm>
#include <chrono>

namespace tgw::core {

RateCap::RateCap(double max_rate_hz) : rate_per_ns_(max_rate_hz / 1e9) {}

bool RateCap::admit(base::SteadyTime now) {
    if (started_ && now > last_) {
        const auto elapsed_ns = static_cast<double>(std::chrono::nanoseconds(now - last_).count());
        tokens_ = std::min(1.0, tokens_ + elapsed_ns * rate_per_ns_);
    }
    // A clock that steps back earns nothing.
    if (!started_ || now > last_) {
        last_ = now;
        started_ = true;
    }
    if (tokens_ < 1.0 - EARLY_FRACTION)
        return false;
    tokens_ -= 1.0;
    return true;
}

}  // namespace tgw::core
