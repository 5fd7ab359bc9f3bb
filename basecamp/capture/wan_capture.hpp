// What the base camp keeps of each sample it takes off the WAN domain (tm-basecamp record, relay --out): the
// recording's rows, and the per-writer tally that the receiver reports to the gateways are made of.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "base/time.hpp"
#include "basecamp/capture/delivery_tally.hpp"
#include "basecamp/recording/sample_store.hpp"
#include "passthrough/discovery.hpp"

namespace tgw::basecamp {

/// The recording's description of a topic as its WAN writer announced it.
TopicRecord topic_record(const passthrough::DiscoveredPublisher& publisher);

/// One recording row: `payload` as received, the writer's source timestamp, the reception time, and the
/// instance of a keyed topic.
SampleRecord sample_record(const TopicRecord& topic, std::vector<std::uint8_t> payload,
                           const eprosima::fastdds::dds::SampleInfo& info);

/// The GUID of the writer of the sample `info` describes.
WriterGuid writer_guid(const eprosima::fastdds::dds::SampleInfo& info);
/// The GUID prefix of that writer: its participant.
ParticipantPrefix writer_prefix(const eprosima::fastdds::dds::SampleInfo& info);

/// When the sample `info` describes was received (now when DDS does not say), wall clock nanoseconds.
std::int64_t receive_ns(const eprosima::fastdds::dds::SampleInfo& info);

/// How long after its source timestamp the sample was received, on two clocks (it may be negative); nullopt
/// without a source timestamp.
std::optional<base::Duration> one_way_delay(const eprosima::fastdds::dds::SampleInfo& info);

/// Counts a received sample of `topic` against its writer (sequence number and payload bytes) for the receiver
/// reports. The gateway's status is not counted: the reports tell the gateway what became of its scheduled
/// samples, and the status is not one of them.
void tally_sample(DeliveryTally& tally, const TopicRecord& topic, const eprosima::fastdds::dds::SampleInfo& info,
                  std::size_t payload_bytes);

}  // namespace tgw::basecamp
