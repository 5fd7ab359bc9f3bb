// Fast DDS 2.9 sets partitions on a Publisher or Subscriber, not on its readers and writers: a participant that
// mirrors publishers in several partition sets needs one of them per set.
#pragma once

#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include "passthrough/offered_qos.hpp"

namespace tgw::passthrough {

/// The Subscribers (or Publishers) of one participant, one per partition set, each made on first use with the
/// participant's default QoS and those partitions. The participant owns them. Not thread-safe.
template <typename Group>
class PartitionGroups {
  public:
    /// The group for `offer`'s partitions; nullptr (not remembered) when Fast DDS refuses it.
    Group* get(eprosima::fastdds::dds::DomainParticipant* participant, const OfferedQos& offer) {
        const auto it = groups_.find(offer.partitions);
        if (it != groups_.end()) {
            return it->second;
        }
        Group* group = create(participant, offer.partition_policy());
        if (group != nullptr) {
            groups_.emplace(offer.partitions, group);
        }
        return group;
    }

    /// Forgets every group: their participant deleted them with itself.
    void forget() { groups_.clear(); }

  private:
    static Group* create(eprosima::fastdds::dds::DomainParticipant* participant,
                         const eprosima::fastdds::dds::PartitionQosPolicy& partitions) {
        if constexpr (std::is_same_v<Group, eprosima::fastdds::dds::Subscriber>) {
            eprosima::fastdds::dds::SubscriberQos qos = participant->get_default_subscriber_qos();
            qos.partition() = partitions;
            return participant->create_subscriber(qos);
        } else {
            eprosima::fastdds::dds::PublisherQos qos = participant->get_default_publisher_qos();
            qos.partition() = partitions;
            return participant->create_publisher(qos);
        }
    }

    std::map<std::vector<std::string>, Group*> groups_;
};

}  // namespace tgw::passthrough
