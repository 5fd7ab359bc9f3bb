// Fast DDS 2.9 builds a DynamicType from every complete XTypes TypeObject a remote endpoint announces, in its
// discovery thread, and crashes there (SIGSEGV in TypeObjectFactory) when the TypeObject holds a sequence of a
// type this process does not know. A robot program built with `fastddsgen -typeobject` would take the gateway
// down, and a base-camp tool the relay. Every participant of the project therefore has a listener that takes the
// TypeObject out of an endpoint's discovery data before Fast DDS reads it; the project reads it itself
// (type_object_idl()), without building anything.
#pragma once

#include <memory>

#include <fastdds/dds/domain/DomainParticipantListener.hpp>

namespace eprosima::fastrtps::types {
class TypeObject;
}  // namespace eprosima::fastrtps::types

namespace tgw::passthrough {

/// Takes the TypeObject and type identifier out of the data of a writer `participant` discovered; the TypeObject
/// when it was a complete one, else nullptr. The participant's own writers are reported too: theirs stay, for
/// they announce them (passthrough_topic()).
std::shared_ptr<const eprosima::fastrtps::types::TypeObject> take_type_object(
    const eprosima::fastdds::dds::DomainParticipant* participant,
    const eprosima::fastrtps::rtps::WriterProxyData& data);

/// The same for a discovered reader, whose TypeObject the project has no use for.
void drop_type_object(const eprosima::fastdds::dds::DomainParticipant* participant,
                      const eprosima::fastrtps::rtps::ReaderProxyData& data);

/// A participant listener that does only that: the base of the project's participant listeners, and the
/// listener of participants that need no other.
class TypeObjectGuard : public eprosima::fastdds::dds::DomainParticipantListener {
  public:
    void on_publisher_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override;
    void on_subscriber_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                 eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) override;
};

}  // namespace tgw::passthrough
