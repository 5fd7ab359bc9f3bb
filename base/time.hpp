#pragma once

#include <chrono>
#include <cstdint>

namespace tgw::base {

/// Scheduling time: monotonic, never jumps. Deadlines, arrivals and the link budget use it.
using SteadyClock = std::chrono::steady_clock;
using SteadyTime = SteadyClock::time_point;

/// Source timestamps as publishers stamp them: wall clock. Converted to SteadyTime once, at the edge.
using WallClock = std::chrono::system_clock;
using WallTime = WallClock::time_point;

using Duration = std::chrono::nanoseconds;

inline double to_seconds(Duration d) {
    return std::chrono::duration<double>(d).count();
}

inline Duration from_seconds(double s) {
    return std::chrono::duration_cast<Duration>(std::chrono::duration<double>(s));
}

inline std::int64_t to_ns(WallTime t) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

inline WallTime wall_from_ns(std::int64_t ns) {
    return WallTime(std::chrono::duration_cast<WallClock::duration>(std::chrono::nanoseconds(ns)));
}

}  // namespace tgw::base
