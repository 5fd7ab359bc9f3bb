#pragma once

#include <optional>
#include <string_view>

namespace tgw::core {

/// The scheduling policies of docs/design.md §4.
enum class PolicyKind {
    ttl,    ///< the default: shortest TTL first, nearest deadline among equals, budgeted, early drop
    edf,    ///< nearest deadline first across all topics, budgeted, early drop: the textbook baseline
    paper,  ///< the 2001 paper's periodic greedy filter
    fifo,   ///< forward as received, no budget: the control
};

std::string_view to_string(PolicyKind p);
std::optional<PolicyKind> parse_policy(std::string_view name);

}  // namespace tgw::core
