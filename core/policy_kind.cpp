#include "core/policy_kind.hpp"

namespace tgw::core {

std::string_view to_string(PolicyKind p) {
    switch (p) {
        case PolicyKind::ttl:
            return "ttl";
        case PolicyKind::edf:
            return "edf";
        case PolicyKind::paper:
            return "paper";
        case PolicyKind::fifo:
            return "fifo";
    }
    return "?";
}

std::optional<PolicyKind> parse_policy(std::string_view name) {
    for (PolicyKind p : {PolicyKind::ttl, PolicyKind::edf, PolicyKind::paper, PolicyKind::fifo}) {
        if (to_string(p) == name)
            return p;
    }
    return std::nullopt;
}

}  // namespace tgw::core
