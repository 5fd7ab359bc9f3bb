#include "core/granted_rate.hpp"

#include <algorithm>

namespace tgw::core {

double granted_rate_bps(double sensed_bps, const GrantView& view, double least_share_bps) {
    if (view.grant_bps)
        return std::min(sensed_bps, std::max(*view.grant_bps, least_share_bps));
    std::optional<double> share = view.newcomer_bps;
    if (!share && view.joining)
        share = JOIN_SHARE * sensed_bps;
    return share ? std::min(sensed_bps, std::max(*share, NEWCOMER_LEAST_SHARE_FACTOR * least_share_bps)) : sensed_bps;
}

}  // namespace tgw::core
