#pragma once

#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include "gateway/dds/robot_transport.hpp"
#include "passthrough/offered_qos.hpp"
#include "passthrough/partition_groups.hpp"

namespace tgw::dds {

/// The gateway's participant on the robot domain. It stays on this host: UDP on the loopback interface (or the
/// addresses given), reaching every process of the host whatever user runs it (base::apply_host_transport). It
/// discovers every publisher (its listener) and holds the type-agnostic readers; it writes only the uplink's commands
/// (Uplink).
class RobotParticipant {
  public:
    /// Throws base::ConfigError if the participant cannot be created. `listener` must outlive this object
    /// and receives discovery callbacks from the moment the participant exists. `base` is the starting QoS
    /// (an XML participant profile, or the default); transports and name are set here. `transport.interfaces`
    /// must be addresses.
    RobotParticipant(int domain, eprosima::fastdds::dds::DomainParticipantListener* listener,
                     const RobotTransport& transport,
                     const std::optional<eprosima::fastdds::dds::DomainParticipantQos>& base);
    ~RobotParticipant();

    RobotParticipant(const RobotParticipant&) = delete;
    RobotParticipant& operator=(const RobotParticipant&) = delete;

    /// A passthrough reader of `topic` that matches every publisher offering `offer` (OfferedQos), in its
    /// partitions. Returns nullptr on failure, after logging it.
    eprosima::fastdds::dds::DataReader* create_reader(const std::string& topic, const std::string& type_name,
                                                      bool keyed, const passthrough::OfferedQos& offer,
                                                      eprosima::fastdds::dds::DataReaderListener* listener);

    /// Detaches the listener and deletes the reader (its topic goes with the topic's last reader).
    void delete_reader(eprosima::fastdds::dds::DataReader* reader);

    eprosima::fastrtps::rtps::GuidPrefix_t guid_prefix() const;
    /// The participant, for the uplink's writers (Uplink), which it must outlive.
    eprosima::fastdds::dds::DomainParticipant* participant() const { return participant_; }

  private:
    eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
    passthrough::PartitionGroups<eprosima::fastdds::dds::Subscriber> subscribers_;
    std::map<std::string, int> readers_of_topic_;
    std::mutex mutex_;
};

}  // namespace tgw::dds
