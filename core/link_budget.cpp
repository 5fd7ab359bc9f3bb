#include "core/link_budget.hpp"

#include <algorithm>

namespace tgw::core {

LinkBudget::LinkBudget(double rate_bps, base::Duration lead) : rate_bps_(rate_bps), lead_(lead) {}

base::Duration LinkBudget::transmit_time(std::uint64_t bits) const {
    if (rate_bps_ <= 0.0) {
        return base::Duration::max();
    }
    return base::from_seconds(static_cast<double>(bits) / rate_bps_);
}

base::SteadyTime LinkBudget::charge(base::SteadyTime now, std::uint64_t bits) {
    busy_until_ = std::max(now, busy_until_) + transmit_time(bits);
    return busy_until_;
}

}  // namespace tgw::core
