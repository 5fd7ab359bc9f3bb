#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <fastdds/dds/topic/TopicDataType.hpp>

namespace tgw::test {

/// A sample written exactly as given, encapsulation included: how a buggy or hostile participant puts malformed
/// bytes on a topic under another type's name.
struct RawSample {
    std::vector<std::uint8_t> bytes;
    std::uint8_t key = 0;  ///< one byte of the instance's key hash: samples with distinct keys never replace each other
};

class RawSampleType final : public eprosima::fastdds::dds::TopicDataType {
  public:
    RawSampleType(const std::string& type_name, bool keyed) {
        setName(type_name.c_str());
        m_typeSize = 64 * 1024;
        m_isGetKeyDefined = keyed;
        auto_fill_type_object(false);
        auto_fill_type_information(false);
    }

    bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
        const auto* sample = static_cast<const RawSample*>(data);
        payload->reserve(static_cast<std::uint32_t>(sample->bytes.size()));
        if (!sample->bytes.empty()) {
            std::memcpy(payload->data, sample->bytes.data(), sample->bytes.size());
        }
        payload->length = static_cast<std::uint32_t>(sample->bytes.size());
        return true;
    }

    bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
        auto* sample = static_cast<RawSample*>(data);
        sample->bytes.assign(payload->data, payload->data + payload->length);
        return true;
    }

    std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
        return [data] { return static_cast<std::uint32_t>(static_cast<RawSample*>(data)->bytes.size()); };
    }

    void* createData() override { return new RawSample(); }
    void deleteData(void* data) override { delete static_cast<RawSample*>(data); }

    bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool = false) override {
        if (!m_isGetKeyDefined) {
            return false;
        }
        std::memset(handle->value, 0, sizeof handle->value);
        handle->value[0] = static_cast<RawSample*>(data)->key;
        handle->value[15] = 0x5a;  // never the zero handle, which means "no key"
        return true;
    }
};

}  // namespace tgw::test
