#pragma once

#include <array>
#include <cstddef>
#include <string_view>

namespace tgw::core {

/// Why a sample went to the on-robot log instead of the WAN.
enum class DropReason {
    expired,       ///< its deadline passed while it waited
    doomed,        ///< it could no longer arrive before its deadline at the current rate
    evicted,       ///< the queue's memory cap was reached and it was the least urgent
    oversize,      ///< its wire time would block a more urgent topic, and it could no longer wait
    shutdown,      ///< still queued when the gateway stopped
    write_failed,  ///< released, but the WAN writer refused it: it never left the robot
    no_reader,     ///< its deadline passed while no base-camp reader took its topic: held back, not sent to no one
    rate_capped,   ///< its topic's max_rate_hz rule thinned it out: more of the topic than the operator wants sent
    superseded,    ///< a newer sample of its instance came while it waited, and its topic's latest_only rule sends that
};

inline constexpr std::size_t DROP_REASON_COUNT = 9;

inline constexpr std::array<std::string_view, DROP_REASON_COUNT> DROP_REASON_NAMES = {
    "expired", "doomed", "evicted", "oversize", "shutdown", "write_failed", "no_reader", "rate_capped", "superseded"};

inline std::string_view to_string(DropReason r) {
    return DROP_REASON_NAMES[static_cast<std::size_t>(r)];
}

}  // namespace tgw::core
