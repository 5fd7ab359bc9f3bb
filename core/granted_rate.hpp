// The rate a gateway under --channel-grants budgets for: its own grant from the base camp, else the newcomers'
// share the base camp grants any gateway it has no grant for, else a joining gateway's small share, else its own
// sensor's rate.
#pragma once

#include <optional>

#include "base/time.hpp"

namespace tgw::core {

/// The fraction of the channel the base camp keeps out of the robots' grants for gateways that join (a robot that
/// starts, a gateway restarted): their share until their first own grant, so that they cost the others' deadlines
/// nothing. A joining gateway that has heard no grant at all budgets this fraction of its own sensed rate.
inline constexpr double JOIN_SHARE = 0.1;
/// A gateway that has heard no grant at all this long after it starts (no base camp grants) budgets for its own
/// sensor. Long, because the WAN's discovery and the first grant cross a slow and busy channel: a gateway restarted
/// in a fleet of three at 60,000 bit/s heard its first grant about 10 s after it started.
inline constexpr base::Duration JOIN_WAIT = std::chrono::seconds(30);

/// Where a gateway stands with the base camp's grants.
struct GrantView {
    std::optional<double> grant_bps;     ///< its own grant in force, if any
    std::optional<double> newcomer_bps;  ///< the newcomers' share in force, if any
    bool joining = false;                ///< no grant of either kind heard yet, within JOIN_WAIT of its start
};

/// A gateway without a grant of its own budgets at least this many times its least share: it must get a status to
/// the base camp to be granted anything, and at its least share exactly the traffic of its discovery went first
/// and the status expired, every time (a gateway restarted in a fleet of three: 15 statuses made, none left).
inline constexpr double NEWCOMER_LEAST_SHARE_FACTOR = 2.0;

/// The rate to budget for, never above the sensed rate: the first of its own grant, the newcomers' share, and (while
/// joining) JOIN_SHARE of the sensed rate, but not below `least_share_bps` (what its status and most urgent sample
/// need, core::least_share_bps, as the base camp grants it), NEWCOMER_LEAST_SHARE_FACTOR times that without a grant
/// of its own; the sensed rate when none applies.
double granted_rate_bps(double sensed_bps, const GrantView& view, double least_share_bps);

}  // namespace tgw::core
