#include "core/link_reserve.hpp"

#include <algorithm>

namespace tgw::core {

std::uint64_t LinkReserve::uncovered(base::SteadyTime now, std::uint64_t bits, double reserve_bps) {
    if (now > time_) {
        bits_ = std::min(bits_ + reserve_bps * base::to_seconds(now - time_), reserve_bps * base::to_seconds(window_));
        time_ = now;
    }
    const double covered = std::min(bits_, static_cast<double>(bits));
    bits_ -= covered;
    return bits - static_cast<std::uint64_t>(covered);
}

}  // namespace tgw::core
