#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <fastdds/dds/core/policy/QosPolicies.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/publisher/qos/PublisherQos.hpp>
#include <fastdds/dds/publisher/qos/WriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/subscriber/qos/SubscriberQos.hpp>

#include "base/time.hpp"

namespace tgw::passthrough {

/// What a robot-domain publisher offers that decides which readers may match it: the gateway reads it with a
/// reader that asks for exactly this, and republishes through a WAN writer that offers exactly this, so any
/// base-camp reader that would have matched the publisher matches the gateway (docs/design.md §3). History
/// depth and Lifespan are not part of it: they are the gateway's. Publishers of one topic that offer the same
/// OfferedQos share a lane of the topic: one robot reader, one WAN writer.
struct OfferedQos {
    enum class Liveliness { automatic, manual_by_participant, manual_by_topic };

    bool reliable = false;
    bool transient_local = false;         ///< TRANSIENT_LOCAL or stronger ("latched")
    std::vector<std::string> partitions;  ///< sorted; empty: the default partition
    std::optional<base::Duration> deadline;
    Liveliness liveliness = Liveliness::automatic;
    std::optional<base::Duration> liveliness_lease;
    bool exclusive_ownership = false;
    std::uint32_t ownership_strength = 0;
    bool xcdr2 = false;  ///< the publisher writes XCDR2 (its first data representation)
    /// The robot reader must ask for inline QoS to learn each sample's instance: a keyed Fast DDS writer sends
    /// the key hash only to readers that do, and a type-agnostic reader cannot compute it. Cyclone DDS
    /// refuses to match such readers (docs/design.md §7), but sends the key hash anyway.
    bool needs_inline_key_hash = false;

    /// Reads the offer from a discovered writer's QoS; `fast_dds_keyed`: the writer is a Fast DDS writer of a
    /// keyed topic (see needs_inline_key_hash).
    static OfferedQos from_writer(const eprosima::fastdds::dds::WriterQos& qos, bool fast_dds_keyed = false);

    /// A robot reader that matches every publisher offering this, and only through these partitions.
    void apply_to_robot_reader(eprosima::fastdds::dds::DataReaderQos& reader) const;
    /// The WAN writer offers what the publisher did (reliability, durability, deadline, liveliness,
    /// ownership, representation); history and Lifespan are left to the caller.
    void apply_to_wan_writer(eprosima::fastdds::dds::DataWriterQos& writer) const;
    /// Partitions live on the publisher and subscriber in Fast DDS 2.9.
    eprosima::fastdds::dds::PartitionQosPolicy partition_policy() const;

    /// A robot reader that asks for this (apply_to_robot_reader) matches a writer that offers `publisher`, and
    /// sees its instances: the lane a --qos profile declared can carry that publisher.
    bool accepts(const OfferedQos& publisher) const {
        return (!reliable || publisher.reliable) && (!transient_local || publisher.transient_local) &&
               partitions == publisher.partitions && exclusive_ownership == publisher.exclusive_ownership &&
               needs_inline_key_hash == publisher.needs_inline_key_hash;
    }

    /// "reliable transient-local partitions=a,b ...": for logs and summaries.
    std::string describe() const;

    auto tied() const {
        return std::tie(reliable, transient_local, partitions, deadline, liveliness, liveliness_lease,
                        exclusive_ownership, ownership_strength, xcdr2, needs_inline_key_hash);
    }
    bool operator==(const OfferedQos& other) const { return tied() == other.tied(); }
    bool operator!=(const OfferedQos& other) const { return !(*this == other); }
};

}  // namespace tgw::passthrough
