// What the base camp itself sends on a fleet's shared channel, as a rate: its commands to a robot, read as the
// uplink's running count of bytes.
#pragma once

#include <cstdint>
#include <deque>

#include "base/time.hpp"

namespace tgw::core {

/// The bit/s of a running byte count, over the last DEMAND_WINDOW (as the base camp reads a robot's demand), or
/// over the time since the count last stood still when that is shorter (MIN_ACTIVE at least): commands that have
/// just begun count at their rate at once, not spread over the window.
class SentRate {
  public:
    /// `total_bytes` sent so far, at `now`; each call no earlier than the last.
    void update(base::SteadyTime now, std::uint64_t total_bytes);
    /// 0 before anything was sent, and once nothing was for a window.
    double bps(base::SteadyTime now) const;

  private:
    struct Reading {
        base::SteadyTime at;
        std::uint64_t bytes = 0;
    };
    /// The newest reading at least a window old, then every one after it.
    std::deque<Reading> readings_;
};

}  // namespace tgw::core
