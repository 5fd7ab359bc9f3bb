#pragma once

#include <cstdint>
#include <vector>

#include "gateway/core/time.hpp"

namespace tgw::sim {

/// A link rate over time as steps: each step's rate holds from its offset until the next step's. Before the
/// first step the first rate holds; after the last, the last.
class RateProfile {
  public:
    struct Step {
        core::Duration at;
        double rate_bps;
    };

    static RateProfile constant(double rate_bps) { return RateProfile({{core::Duration::zero(), rate_bps}}); }
    /// `steps` must be non-empty with strictly increasing offsets.
    explicit RateProfile(std::vector<Step> steps);

    double rate_at(core::Duration offset) const;
    /// The offset of the first step after `offset`, or Duration::max() if none.
    core::Duration next_change_after(core::Duration offset) const;
    /// When `bits` started at `offset` have left the link, integrating across rate steps (a step at 0 bit/s
    /// pauses the transmission); Duration::max() if the link never carries them.
    core::Duration finish_offset(core::Duration offset, std::uint64_t bits) const;

    const std::vector<Step>& steps() const { return steps_; }

  private:
    std::size_t step_index(core::Duration offset) const;

    std::vector<Step> steps_;
};

}  // namespace tgw::sim
