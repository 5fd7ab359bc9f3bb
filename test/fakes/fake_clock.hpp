#pragma once

#include "base/clock.hpp"

namespace tgw::test {

/// A clock that moves only when told. Both time lines advance together.
class FakeClock final : public base::Clock {
  public:
    FakeClock() : steady_(std::chrono::seconds(1000)), wall_(std::chrono::seconds(1'700'000'000)) {}

    base::SteadyTime now() const override { return steady_; }
    base::WallTime wall_now() const override { return wall_; }

    void advance(base::Duration d) {
        steady_ += d;
        wall_ += std::chrono::duration_cast<base::WallClock::duration>(d);
    }

  private:
    base::SteadyTime steady_;
    base::WallTime wall_;
};

}  // namespace tgw::test
