#include "basecamp/status/gateway_status.hpp"

#include <algorithm>
#include <exception>

#include "GatewayStatusPubSubTypes.h"

namespace tgw::basecamp {

std::optional<idl::GatewayStatus> decode_gateway_status(const std::vector<std::uint8_t>& payload) {
    eprosima::fastrtps::rtps::SerializedPayload_t serialized(static_cast<std::uint32_t>(payload.size()));
    std::copy(payload.begin(), payload.end(), serialized.data);
    serialized.length = static_cast<std::uint32_t>(payload.size());
    idl::GatewayStatus status;
    idl::GatewayStatusPubSubType type;
    // The type support turns a truncated buffer into false; Fast-CDR throws for other malformed input (a bad
    // encapsulation, a sequence length beyond memory).
    try {
        if (!type.deserialize(&serialized, &status)) {
            return std::nullopt;
        }
    } catch (const std::exception&) {
        return std::nullopt;
    }
    return status;
}

std::uint64_t logged_on_robot(const idl::TopicStatus& topic) {
    return topic.expired() + topic.doomed() + topic.evicted() + topic.oversize() + topic.shutdown() +
           topic.write_failed() + topic.no_reader() + topic.rate_capped() + topic.superseded();
}

}  // namespace tgw::basecamp
