#include "passthrough/type_object_guard.hpp"

#include <fastdds/rtps/builtin/data/ReaderProxyData.h>
#include <fastdds/rtps/builtin/data/WriterProxyData.h>
#include <fastdds/rtps/reader/ReaderDiscoveryInfo.h>
#include <fastdds/rtps/writer/WriterDiscoveryInfo.h>
#include <fastrtps/types/TypeObject.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>

namespace tgw::passthrough {

namespace types = eprosima::fastrtps::types;

namespace {

/// Leaves `data` with neither, so that Fast DDS finds nothing to build a DynamicType from. The data is Fast DDS's
/// own record of the endpoint, handed to the listener as const; it is not const itself, and the listener runs
/// while discovery holds it.
template <typename ProxyData>
std::shared_ptr<const types::TypeObject> take(const eprosima::fastdds::dds::DomainParticipant* participant,
                                              const ProxyData& announced) {
    if (participant != nullptr && announced.guid().guidPrefix == participant->guid().guidPrefix)
        return nullptr;
    auto& data = const_cast<ProxyData&>(announced);
    std::shared_ptr<const types::TypeObject> taken;
    if (data.has_type()) {
        if (data.type().m_type_object._d() == types::EK_COMPLETE)
            taken = std::make_shared<types::TypeObject>(data.type().m_type_object);
        data.type().m_type_object = types::TypeObject();
    }
    if (data.has_type_id())
        data.type_id().m_type_identifier = types::TypeIdentifier();
    return taken;
}

}  // namespace

std::shared_ptr<const types::TypeObject> take_type_object(const eprosima::fastdds::dds::DomainParticipant* participant,
                                                          const eprosima::fastrtps::rtps::WriterProxyData& data) {
    return take(participant, data);
}

void drop_type_object(const eprosima::fastdds::dds::DomainParticipant* participant,
                      const eprosima::fastrtps::rtps::ReaderProxyData& data) {
    take(participant, data);
}

void TypeObjectGuard::on_publisher_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                             eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) {
    take_type_object(participant, info.info);
}

void TypeObjectGuard::on_subscriber_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                              eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) {
    drop_type_object(participant, info.info);
}

}  // namespace tgw::passthrough
