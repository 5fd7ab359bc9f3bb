// The QoS of a camp writer whose each sample says all there is for one gateway: receiver reports, channel grants.
#pragma once

#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>

namespace eprosima::fastdds::dds {
class Publisher;
}  // namespace eprosima::fastdds::dds

namespace tgw::basecamp {

/// `publisher`'s default writer QoS made reliable, volatile and keep last 1, without data sharing: only the newest
/// sample per gateway matters, a write never waits, a camp tool's reliable reader (ROS 2's default) matches it, and
/// so do the gateways' best-effort readers.
eprosima::fastdds::dds::DataWriterQos latest_per_gateway_qos(const eprosima::fastdds::dds::Publisher& publisher);

}  // namespace tgw::basecamp
