#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "base/time.hpp"

namespace tgw::base {

/// A link rate over time as steps: each step's rate holds from its offset until the next step's. Before the
/// first step the first rate holds (a trace that starts at 5 s still has a rate at 0 s); after the last, the
/// last rate holds forever. What a rate trace file holds (sensor::RateTrace) and what the simulator's link
/// follows (sim::RateProfile).
class RateSteps {
  public:
    struct Step {
        Duration at;  ///< since the start
        double rate_bps;
    };

    /// `steps` must be non-empty, with strictly increasing offsets.
    explicit RateSteps(std::vector<Step> steps) : steps_(std::move(steps)) {}

    /// The rate of the last step at or before `offset`; the first step's rate before the first step.
    double rate_at(Duration offset) const { return steps_[step_index(offset)].rate_bps; }
    /// The offset of the first step after `offset`, or Duration::max() if none.
    Duration next_change_after(Duration offset) const;

    const std::vector<Step>& steps() const { return steps_; }

  protected:
    /// The index of the step in force at `offset`: 0 before the first step.
    std::size_t step_index(Duration offset) const;

  private:
    std::vector<Step> steps_;
};

}  // namespace tgw::base
