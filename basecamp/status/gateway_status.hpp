// The gateway's status (tgw/status, idl/GatewayStatus.idl) as base-camp tools get it: serialized, from a
// type-agnostic reader.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "GatewayStatus.h"

namespace tgw::basecamp {

/// nullopt when `payload` (encapsulation header included) is not a GatewayStatus.
std::optional<idl::GatewayStatus> decode_gateway_status(const std::vector<std::uint8_t>& payload);

/// What went to the on-robot log instead of the link, all reasons together.
std::uint64_t logged_on_robot(const idl::TopicStatus& topic);

}  // namespace tgw::basecamp
