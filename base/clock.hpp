#pragma once

#include "base/time.hpp"

namespace tgw::base {

/// Where the gateway reads the time. Injected so that tests and tm-sim run in simulated time.
class Clock {
  public:
    virtual ~Clock() = default;
    virtual SteadyTime now() const = 0;
    virtual WallTime wall_now() const = 0;

    /// The steady time at which the wall clock read `wall`, assuming neither clock drifts in between.
    SteadyTime to_steady(WallTime wall) const {
        return now() + std::chrono::duration_cast<Duration>(wall - wall_now());
    }
};

/// The real clocks of this machine.
class SystemClock final : public Clock {
  public:
    SteadyTime now() const override { return SteadyClock::now(); }
    WallTime wall_now() const override { return WallClock::now(); }
};

}  // namespace tgw::base
