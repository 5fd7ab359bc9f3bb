#include "gateway/sim/simulated_link.hpp"

#include <algorithm>

namespace tgw::sim {

SimulatedLink::SimulatedLink(RateProfile rate, core::SteadyTime start, core::Duration queue_limit)
    : rate_(std::move(rate)), start_(start), queue_limit_(queue_limit), busy_until_(start) {}

std::optional<core::SteadyTime> SimulatedLink::send(core::SteadyTime now, std::uint64_t bits) {
    const core::SteadyTime begin = std::max(now, busy_until_);
    if (begin - now > queue_limit_) {
        dropped_bits_ += bits;
        return std::nullopt;
    }
    const core::Duration finish = rate_.finish_offset(begin - start_, bits);
    if (finish == core::Duration::max()) {
        dropped_bits_ += bits;
        return std::nullopt;
    }
    busy_until_ = start_ + finish;
    sent_bits_ += bits;
    return busy_until_;
}

}  // namespace tgw::sim
