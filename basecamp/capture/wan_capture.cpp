#include "basecamp/capture/wan_capture.hpp"

#include <algorithm>
#include <iterator>

#include "base/time.hpp"
#include "passthrough/dds_time.hpp"
#include "passthrough/type_object_idl.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {

TopicRecord topic_record(const passthrough::DiscoveredPublisher& publisher) {
    TopicRecord record;
    record.topic = publisher.topic;
    record.type_name = publisher.type_name;
    if (publisher.lifespan)
        record.lifespan_ns = publisher.lifespan->count();
    record.keyed = publisher.keyed;
    record.reliable = publisher.qos.reliable;
    record.discovered_ns = base::to_ns(base::WallClock::now());
    if (publisher.type_object) {
        const passthrough::TypeObjectIdl announced =
            passthrough::type_object_idl(*publisher.type_object, publisher.type_name, {});
        if (announced.ok())
            record.announced_idl = announced.text;
    }
    return record;
}

SampleRecord sample_record(const TopicRecord& topic, std::vector<std::uint8_t> payload,
                           const eprosima::fastdds::dds::SampleInfo& info) {
    SampleRecord record;
    record.topic = topic.topic;
    record.type_name = topic.type_name;
    record.payload = std::move(payload);
    const auto source = passthrough::to_wall_time(info.source_timestamp);
    record.source_ns = source ? base::to_ns(*source) : 0;
    record.receive_ns = receive_ns(info);
    record.lifespan_ns = topic.lifespan_ns;
    if (topic.keyed) {
        for (std::size_t i = 0; i < 16; ++i)
            record.instance.push_back(info.instance_handle.value[i]);
    }
    return record;
}

void tally_sample(DeliveryTally& tally, const TopicRecord& topic, const eprosima::fastdds::dds::SampleInfo& info,
                  std::size_t payload_bytes) {
    if (topic.topic == wire::STATUS_TOPIC) {
        return;
    }
    tally.add(writer_guid(info), info.sample_identity.sequence_number().to64long(), payload_bytes);
}

WriterGuid writer_guid(const eprosima::fastdds::dds::SampleInfo& info) {
    const auto& guid = info.sample_identity.writer_guid();
    WriterGuid writer;
    std::copy(std::begin(guid.guidPrefix.value), std::end(guid.guidPrefix.value), writer.begin());
    std::copy(std::begin(guid.entityId.value), std::end(guid.entityId.value),
              writer.begin() + sizeof(guid.guidPrefix.value));
    return writer;
}

ParticipantPrefix writer_prefix(const eprosima::fastdds::dds::SampleInfo& info) {
    ParticipantPrefix prefix;
    const auto& value = info.sample_identity.writer_guid().guidPrefix.value;
    std::copy(std::begin(value), std::end(value), prefix.begin());
    return prefix;
}

std::int64_t receive_ns(const eprosima::fastdds::dds::SampleInfo& info) {
    const auto reception = passthrough::to_wall_time(info.reception_timestamp);
    return base::to_ns(reception ? *reception : base::WallClock::now());
}

std::optional<base::Duration> one_way_delay(const eprosima::fastdds::dds::SampleInfo& info) {
    const auto source = passthrough::to_wall_time(info.source_timestamp);
    if (!source)
        return std::nullopt;
    return std::chrono::nanoseconds(receive_ns(info) - base::to_ns(*source));
}

}  // namespace tgw::basecamp
