// Where tm-robot-sim's robot drives, and the radio field it drives through: for the link-quality map
// (tm-basecamp linkmap), the same route and field for the poses it publishes and the rate trace that shapes the
// link (scripts/linkmap-demo).
#pragma once

#include <ostream>

namespace tgw::robot_sim {

struct Pose {
    double x = 0, y = 0;     ///< metres, the base camp at the origin, x east, y north
    double heading_rad = 0;  ///< counter-clockwise from x
};

/// A survey loop from the base camp: 240 m east, 120 m north, back west, back south, at 12 m/s: 60 s a lap,
/// repeated.
Pose survey_pose(double seconds);

/// The link rate the simulated field gives at `pose`: 70 kbit/s at the camp, falling with distance (e-folding
/// 150 m) towards 10 kbit/s, and 40 % of that in the radio shadow of a hill around (200 m, 100 m), 50 m across.
double field_rate_bps(const Pose& pose);

/// The rate along the route, one step a second from 0 to `seconds`, as `seconds bits_per_second` lines: the trace
/// format of the gateway's --sensor trace:FILE.
void write_field_trace(std::ostream& out, double seconds);

}  // namespace tgw::robot_sim
