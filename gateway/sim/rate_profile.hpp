#pragma once

#include <cstdint>
#include <utility>

#include "base/rate_steps.hpp"

namespace tgw::sim {

/// The simulated link's rate over time (base::RateSteps), and how long bits take across its steps.
class RateProfile : public base::RateSteps {
  public:
    using RateSteps::RateSteps;
    explicit RateProfile(base::RateSteps steps) : RateSteps(std::move(steps)) {}

    static RateProfile constant(double rate_bps) { return RateProfile({{base::Duration::zero(), rate_bps}}); }

    /// When `bits` started at `offset` have left the link, integrating across rate steps (a step at 0 bit/s
    /// pauses the transmission); Duration::max() if the link never carries them.
    base::Duration finish_offset(base::Duration offset, std::uint64_t bits) const;
    /// The bits the link carries from `from` to `to` when never idle.
    double capacity_bits(base::Duration from, base::Duration to) const;
};

}  // namespace tgw::sim
