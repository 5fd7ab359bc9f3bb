// The QoS of a type-agnostic reader and writer that pass one publisher's samples on, unchanged: the gateway's
// robot reader and WAN writer, and tm-basecamp relay's WAN reader and local writer.
#pragma once

#include <optional>

#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

#include "base/time.hpp"
#include "passthrough/offered_qos.hpp"

namespace tgw::passthrough {

/// `base` made into a reader that matches every publisher offering exactly `offer` and takes every sample as it
/// comes: keep last 1000 per instance, room for 65,536 instances, no data sharing, and for keyed topics
/// preallocated payloads (Fast DDS 2.9's dynamic payload pools drop a dispose's or unregister's empty payload).
eprosima::fastdds::dds::DataReaderQos passthrough_reader_qos(eprosima::fastdds::dds::DataReaderQos base,
                                                             const OfferedQos& offer, bool keyed);

/// `base` made into a writer that offers what `offer` says, with Lifespan `lifespan` (nullopt: infinite), and
/// keeps what a reader may still ask for: keep last 64 per instance on a reliable volatile lane (repairs), 1
/// otherwise (a latched topic's last sample per instance). An unregister stays an unregister (no autodispose);
/// keyed topics preallocate payloads, as the reader does.
eprosima::fastdds::dds::DataWriterQos passthrough_writer_qos(eprosima::fastdds::dds::DataWriterQos base,
                                                             const OfferedQos& offer, bool keyed,
                                                             std::optional<base::Duration> lifespan);

}  // namespace tgw::passthrough
