#include "passthrough/discovery.hpp"

#include <algorithm>
#include <utility>

#include <fastdds/rtps/participant/ParticipantDiscoveryInfo.h>
#include <fastdds/rtps/writer/WriterDiscoveryInfo.h>

#include "passthrough/dds_time.hpp"

namespace tgw::passthrough {

using eprosima::fastrtps::rtps::GuidPrefix_t;
using eprosima::fastrtps::rtps::WriterDiscoveryInfo;

namespace {

// RTPS entity kinds (RTPS 2.x, 9.3.1.2): user-defined writers with and without key.
constexpr std::uint8_t ENTITY_KIND_WRITER_WITH_KEY = 0x02;

}  // namespace

DiscoveredPublisher discovered_publisher(const eprosima::fastrtps::rtps::WriterProxyData& data,
                                         std::shared_ptr<const eprosima::fastrtps::types::TypeObject> type_object) {
    DiscoveredPublisher pub;
    pub.topic = data.topicName().to_string();
    pub.type_name = data.typeName().to_string();
    // Vendors announce keyed-ness in the writer's entity kind; Fast DDS also derives topicKind from it.
    pub.keyed = data.topicKind() == eprosima::fastrtps::rtps::WITH_KEY ||
                data.guid().entityId.value[3] == ENTITY_KIND_WRITER_WITH_KEY;
    pub.lifespan = to_duration(data.m_qos.m_lifespan.duration);
    // Fast DDS puts its vendor id in the first two bytes of its GUID prefixes.
    const auto& prefix = data.guid().guidPrefix.value;
    const bool fast_dds = prefix[0] == eprosima::fastrtps::rtps::c_VendorId_eProsima[0] &&
                          prefix[1] == eprosima::fastrtps::rtps::c_VendorId_eProsima[1];
    pub.qos = OfferedQos::from_writer(data.m_qos, fast_dds && pub.keyed);
    pub.writer = data.guid();
    pub.type_object = std::move(type_object);
    return pub;
}

Discovery::Discovery(Callback on_publisher, GoneCallback on_gone)
    : on_publisher_(std::move(on_publisher)), on_gone_(std::move(on_gone)) {}

void Discovery::ignore_participant(const GuidPrefix_t& prefix) {
    std::lock_guard<std::mutex> lock(mutex_);
    ignored_.push_back(prefix);
}

bool Discovery::ignored(const GuidPrefix_t& prefix) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::find(ignored_.begin(), ignored_.end(), prefix) != ignored_.end();
}

void Discovery::on_participant_discovery(eprosima::fastdds::dds::DomainParticipant* /*participant*/,
                                         eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) {
    using Status = eprosima::fastrtps::rtps::ParticipantDiscoveryInfo;
    if (on_participant_ && info.status == Status::DISCOVERED_PARTICIPANT && !ignored(info.info.m_guid.guidPrefix)) {
        on_participant_(info.info.m_guid.guidPrefix);
    }
}

void Discovery::on_publisher_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                       WriterDiscoveryInfo&& info) {
    // A changed QoS keeps the topic's first TTL and its lanes.
    const auto& data = info.info;
    std::shared_ptr<const eprosima::fastrtps::types::TypeObject> type_object = take_type_object(participant, data);
    if (ignored(data.guid().guidPrefix)) {
        return;
    }
    if (info.status == WriterDiscoveryInfo::REMOVED_WRITER) {
        if (on_gone_) {
            on_gone_(data.topicName().to_string(), data.guid());
        }
        return;
    }
    if (info.status != WriterDiscoveryInfo::DISCOVERED_WRITER) {
        return;
    }
    on_publisher_(discovered_publisher(data, std::move(type_object)));
}

}  // namespace tgw::passthrough
