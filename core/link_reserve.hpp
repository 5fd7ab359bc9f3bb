// The rate the budget keeps back, saved up for traffic the scheduler does not release.
#pragma once

#include <cstdint>

#include "base/time.hpp"

namespace tgw::core {

/// The part of the sensed rate the budget does not spend (SchedulerConfig::budget_fraction), saved up over a
/// window: the WAN participant's discovery, heartbeats and repairs charged from outside the schedule
/// (Scheduler::charge_link) cost the samples nothing while it covers them. A participant announcing itself every
/// 20 s fits in a window of 20 s; a burst beyond it holds the budget.
class LinkReserve {
  public:
    explicit LinkReserve(base::Duration window) : window_(window) {}

    /// Of `bits` charged at `now`, what the reserve does not cover; what it covers is spent. It has filled at
    /// `reserve_bps` since the last call, up to a window's worth.
    std::uint64_t uncovered(base::SteadyTime now, std::uint64_t bits, double reserve_bps);

  private:
    base::Duration window_;
    double bits_ = 0.0;  ///< saved, as of time_
    base::SteadyTime time_{};
};

}  // namespace tgw::core
