#pragma once

#include "gateway/core/clock.hpp"

namespace tgw::test {

/// A clock that moves only when told. Both time lines advance together.
class FakeClock final : public core::Clock {
  public:
    FakeClock() : steady_(std::chrono::seconds(1000)), wall_(std::chrono::seconds(1'700'000'000)) {}

    core::SteadyTime now() const override { return steady_; }
    core::WallTime wall_now() const override { return wall_; }

    void advance(core::Duration d) {
        steady_ += d;
        wall_ += std::chrono::duration_cast<core::WallClock::duration>(d);
    }

  private:
    core::SteadyTime steady_;
    core::WallTime wall_;
};

}  // namespace tgw::test
