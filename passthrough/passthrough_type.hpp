#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <fastdds/rtps/common/InstanceHandle.h>
#include <fastdds/dds/topic/TopicDataType.hpp>

namespace eprosima::fastdds::dds {
class DomainParticipant;
class Topic;
}  // namespace eprosima::fastdds::dds

namespace eprosima::fastrtps::types {
class TypeObject;
}  // namespace eprosima::fastrtps::types

namespace tgw::passthrough {

/// One sample of any type as the gateway carries it: the serialized bytes exactly as they came off the wire
/// (encapsulation header included) and, for keyed topics, the instance they belong to.
struct PassthroughData {
    std::vector<std::uint8_t> payload;
    eprosima::fastrtps::rtps::InstanceHandle_t key;
};

/// A Fast DDS TopicDataType for a type the gateway was never compiled with: the type name is set at run time
/// and the payload passes through untouched. The key is never computed from the payload (the type is unknown);
/// getKey() returns the key hash carried with the data: on the reader side Fast DDS takes it from the
/// writer's inline key hash before it asks the type, on the writer side the bridge sets it from the reader's
/// SampleInfo::instance_handle. A keyed sample that arrives without a key hash (a writer that does not send
/// one) is kept under UNKNOWN_INSTANCE rather than rejected.
class PassthroughType final : public eprosima::fastdds::dds::TopicDataType {
  public:
    /// The instance of keyed samples whose key hash was not sent.
    static const eprosima::fastrtps::rtps::InstanceHandle_t UNKNOWN_INSTANCE;

    PassthroughType(const std::string& type_name, bool keyed);

    bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override;
    bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override;
    std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override;
    void* createData() override;
    void deleteData(void* data) override;
    bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool force_md5 = false) override;

    bool keyed() const { return m_isGetKeyDefined; }
};

/// The Topic `topic` of type `type_name` on `participant`, as the gateway and the base camp pass it on: a
/// PassthroughType registered under that name on first use, and the existing Topic if there is one (a topic's
/// lanes share it). nullptr when Fast DDS refuses either.
///
/// `announced`, the TypeObject the original publisher announced (DiscoveredPublisher::type_object), is announced
/// by the participant's writers of the type created from then on, when the type has none yet and it describes the
/// type by itself (type_object_idl() needs no lookup). One that refers to other types helps no reader, who cannot
/// ask for them through the gateway, and crashes Fast DDS 2.9 readers who do not know them (TypeObjectGuard).
eprosima::fastdds::dds::Topic* passthrough_topic(
    eprosima::fastdds::dds::DomainParticipant* participant, const std::string& topic, const std::string& type_name,
    bool keyed, const std::shared_ptr<const eprosima::fastrtps::types::TypeObject>& announced = nullptr);

}  // namespace tgw::passthrough
