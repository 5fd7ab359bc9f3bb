// Serialized gateway statuses, as a type-agnostic base-camp reader receives them.
#pragma once

#include <cstdint>
#include <vector>

#include "GatewayStatusPubSubTypes.h"

namespace tgw::test {

inline std::vector<std::uint8_t> serialized(idl::GatewayStatus status) {
    idl::GatewayStatusPubSubType type;
    eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&status)());
    type.serialize(&status, &payload);
    return std::vector<std::uint8_t>(payload.data, payload.data + payload.length);
}

inline idl::TopicStatus topic_status(const std::string& name, std::uint32_t ttl_ms, std::uint64_t forwarded,
                                     std::uint64_t expired) {
    idl::TopicStatus t;
    t.name(name);
    t.ttl_ms(ttl_ms);
    t.received(forwarded + expired);
    t.forwarded(forwarded);
    t.expired(expired);
    return t;
}

}  // namespace tgw::test
