#include "base/rate_steps.hpp"

#include <algorithm>

namespace tgw::base {

namespace {

/// The first step whose offset is after `offset`.
std::vector<RateSteps::Step>::const_iterator first_after(const std::vector<RateSteps::Step>& steps, Duration offset) {
    return std::upper_bound(steps.begin(), steps.end(), offset,
                            [](Duration t, const RateSteps::Step& step) { return t < step.at; });
}

}  // namespace

Duration RateSteps::next_change_after(Duration offset) const {
    const auto it = first_after(steps_, offset);
    return it == steps_.end() ? Duration::max() : it->at;
}

std::size_t RateSteps::step_index(Duration offset) const {
    const auto it = first_after(steps_, offset);
    return it == steps_.begin() ? 0 : static_cast<std::size_t>(it - steps_.begin() - 1);
}

}  // namespace tgw::base
