#pragma once

#include <fastdds/rtps/common/InstanceHandle.h>
#include <fastdds/rtps/common/SerializedPayload.h>

#include "core/sample.hpp"

namespace tgw::dds {

/// Serializes `data`, of a keyed type the gateway writes itself (its status, the compact catalog), into `out`'s
/// payload and instance, as a sample of that type arrives from the robot. False when the type refuses.
template <typename PubSubType, typename Data>
bool keyed_sample(PubSubType& type, Data& data, core::Sample& out) {
    eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&data)());
    eprosima::fastrtps::rtps::InstanceHandle_t instance;
    if (!type.serialize(&data, &payload) || !type.getKey(&data, &instance, false)) {
        return false;
    }
    out.payload.assign(payload.data, payload.data + payload.length);
    for (std::size_t i = 0; i < out.key.bytes.size(); ++i) {
        out.key.bytes[i] = instance.value[i];
    }
    out.key.valid = true;
    return true;
}

}  // namespace tgw::dds
