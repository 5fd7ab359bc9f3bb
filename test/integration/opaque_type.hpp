#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

#include <fastdds/dds/topic/TopicDataType.hpp>

namespace tgw::test {

/// A type only the test knows: hand-serialized as CDR little endian (uint32 id, then a sequence<octet>),
/// under a type name no IDL of the project has. The gateway must carry it without knowing it.
struct OpaqueBlob {
    std::uint32_t id = 0;
    std::vector<std::uint8_t> bytes;
};

class OpaqueBlobType final : public eprosima::fastdds::dds::TopicDataType {
  public:
    static constexpr const char* TYPE_NAME = "test_only::OpaqueBlob";

    OpaqueBlobType() {
        setName(TYPE_NAME);
        m_typeSize = 4 + 4 + 4 + 1024;
        m_isGetKeyDefined = false;
        auto_fill_type_object(false);
        auto_fill_type_information(false);
    }

    bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
        const auto* blob = static_cast<const OpaqueBlob*>(data);
        const std::uint32_t size = 12 + static_cast<std::uint32_t>(blob->bytes.size());
        payload->reserve(size);
        std::uint8_t* p = payload->data;
        p[0] = 0x00;
        p[1] = 0x01;  // CDR_LE
        p[2] = p[3] = 0x00;
        put_u32(p + 4, blob->id);
        put_u32(p + 8, static_cast<std::uint32_t>(blob->bytes.size()));
        if (!blob->bytes.empty()) {
            std::memcpy(p + 12, blob->bytes.data(), blob->bytes.size());
        }
        payload->length = size;
        payload->encapsulation = CDR_LE;
        return true;
    }

    bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
        auto* blob = static_cast<OpaqueBlob*>(data);
        if (payload->length < 12) {
            return false;
        }
        const std::uint8_t* p = payload->data;
        blob->id = get_u32(p + 4);
        const std::uint32_t n = get_u32(p + 8);
        if (payload->length < 12 + n) {
            return false;
        }
        blob->bytes.assign(p + 12, p + 12 + n);
        return true;
    }

    std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
        const auto* blob = static_cast<const OpaqueBlob*>(data);
        return [blob] { return 12 + static_cast<std::uint32_t>(blob->bytes.size()); };
    }
    void* createData() override { return new OpaqueBlob(); }
    void deleteData(void* data) override { delete static_cast<OpaqueBlob*>(data); }
    bool getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) override { return false; }

  private:
    static void put_u32(std::uint8_t* p, std::uint32_t v) {
        for (int i = 0; i < 4; ++i) {
            p[i] = static_cast<std::uint8_t>(v >> (8 * i));
        }
    }
    static std::uint32_t get_u32(const std::uint8_t* p) {
        return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
    }
};

}  // namespace tgw::test
