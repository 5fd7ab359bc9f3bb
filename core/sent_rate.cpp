#include "core/sent_rate.hpp"

#include <algorithm>

#include "core/demand_watch.hpp"
#include "core/urgency_demand.hpp"

namespace tgw::core {

void SentRate::update(base::SteadyTime now, std::uint64_t total_bytes) {
    readings_.push_back(Reading{now, total_bytes});
    while (readings_.size() > 1 && readings_[1].at <= now - DEMAND_WINDOW)
        readings_.pop_front();
}

double SentRate::bps(base::SteadyTime now) const {
    if (readings_.empty() || readings_.back().bytes <= readings_.front().bytes)
        return 0.0;
    // Where the count last stood still: the sending began after it.
    auto still = readings_.begin();
    while (std::next(still) != readings_.end() && std::next(still)->bytes == readings_.front().bytes)
        ++still;
    const base::Duration elapsed = std::max<base::Duration>(now - still->at, MIN_ACTIVE);
    return 8.0 * static_cast<double>(readings_.back().bytes - still->bytes) / base::to_seconds(elapsed);
}

}  // namespace tgw::core
