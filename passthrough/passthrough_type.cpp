#include "passthrough/passthrough_type.hpp"

#include <cstring>

#include <fastrtps/types/TypeObject.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "passthrough/type_object_idl.hpp"

namespace tgw::passthrough {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::InstanceHandle_t;
using eprosima::fastrtps::rtps::SerializedPayload_t;
using eprosima::fastrtps::types::ReturnCode_t;

namespace {

InstanceHandle_t make_unknown_instance() {
    InstanceHandle_t handle;
    for (std::size_t i = 0; i < 16; ++i) {
        handle.value[i] = 0xff;
    }
    return handle;
}

// A hint for pre-allocation only: endpoints of this type use dynamic payload pools, and larger samples
// are accepted (DDS Router does the same).
constexpr std::uint32_t TYPE_SIZE_HINT_BYTES = 2048;

}  // namespace

const InstanceHandle_t PassthroughType::UNKNOWN_INSTANCE = make_unknown_instance();

PassthroughType::PassthroughType(const std::string& type_name, bool keyed) {
    setName(type_name.c_str());
    m_typeSize = TYPE_SIZE_HINT_BYTES;
    m_isGetKeyDefined = keyed;
    // No type object or type information is known; matching is by type name, as with any vendor.
    auto_fill_type_object(false);
    auto_fill_type_information(false);
}

bool PassthroughType::serialize(void* data, SerializedPayload_t* payload) {
    const auto* sample = static_cast<const PassthroughData*>(data);
    const auto size = static_cast<std::uint32_t>(sample->payload.size());
    if (payload->max_size < size) {
        payload->reserve(size);
    }
    if (size > 0) {
        std::memcpy(payload->data, sample->payload.data(), size);
    }
    payload->length = size;
    // The second byte of the encapsulation header says the byte order; keep what the publisher used.
    payload->encapsulation = (size >= 2 && (sample->payload[1] & 0x01) != 0) ? CDR_LE : CDR_BE;
    return true;
}

bool PassthroughType::deserialize(SerializedPayload_t* payload, void* data) {
    auto* sample = static_cast<PassthroughData*>(data);
    sample->payload.assign(payload->data, payload->data + payload->length);
    return true;
}

std::function<std::uint32_t()> PassthroughType::getSerializedSizeProvider(void* data) {
    const auto* sample = static_cast<const PassthroughData*>(data);
    return [sample] { return static_cast<std::uint32_t>(sample->payload.size()); };
}

void* PassthroughType::createData() {
    return new PassthroughData();
}

void PassthroughType::deleteData(void* data) {
    delete static_cast<PassthroughData*>(data);
}

bool PassthroughType::getKey(void* data, InstanceHandle_t* handle, bool /*force_md5*/) {
    if (!m_isGetKeyDefined) {
        return false;
    }
    const auto* sample = static_cast<const PassthroughData*>(data);
    *handle = sample->key.isDefined() ? sample->key : UNKNOWN_INSTANCE;
    return true;
}

fdds::Topic* passthrough_topic(fdds::DomainParticipant* participant, const std::string& topic,
                               const std::string& type_name, bool keyed,
                               const std::shared_ptr<const eprosima::fastrtps::types::TypeObject>& announced) {
    fdds::TypeSupport type = participant->find_type(type_name);
    if (type.empty()) {
        type = fdds::TypeSupport(new PassthroughType(type_name, keyed));
        if (participant->register_type(type, type_name) != ReturnCode_t::RETCODE_OK) {
            return nullptr;
        }
    }
    if (announced && !type->type_object() && type_object_idl(*announced, type_name, {}).ok()) {
        auto passed_on = std::make_shared<fdds::TypeObjectV1>();
        passed_on->m_type_object = *announced;
        type->type_object(std::move(passed_on));
    }
    if (auto* existing = dynamic_cast<fdds::Topic*>(participant->lookup_topicdescription(topic))) {
        return existing;
    }
    return participant->create_topic(topic, type_name, fdds::TOPIC_QOS_DEFAULT);
}

}  // namespace tgw::passthrough
