#include "gateway/dds/robot_participant.hpp"

#include <cstdint>
#include <iostream>
#include <memory>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include "base/config_error.hpp"
#include "base/host_transport.hpp"
#include "base/receive_buffer.hpp"
#include "passthrough/passthrough_qos.hpp"
#include "passthrough/passthrough_type.hpp"

namespace tgw::dds {

namespace fdds = eprosima::fastdds::dds;

RobotParticipant::RobotParticipant(int domain, fdds::DomainParticipantListener* listener,
                                   const RobotTransport& transport,
                                   const std::optional<fdds::DomainParticipantQos>& base) {
    fdds::DomainParticipantQos qos =
        base ? *base : fdds::DomainParticipantFactory::get_instance()->get_default_participant_qos();
    qos.name("telemetry-gateway/robot");
    base::warn_if_receive_buffer_capped(std::cerr, "telemetry-gateway", "--robot-receive-buffer",
                                        transport.receive_buffer_bytes);
    base::apply_host_transport(qos, domain, {transport.interfaces, transport.shm, transport.receive_buffer_bytes});

    participant_ = fdds::DomainParticipantFactory::get_instance()->create_participant(
        static_cast<fdds::DomainId_t>(domain), qos, listener, fdds::StatusMask::none());
    if (participant_ == nullptr) {
        throw base::ConfigError("--robot-domain " + std::to_string(domain) +
                                ": cannot create the robot participant (see the Fast DDS log)");
    }
    if (subscribers_.get(participant_, passthrough::OfferedQos{}) == nullptr) {
        fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
        throw base::ConfigError("--robot-domain " + std::to_string(domain) + ": cannot create a subscriber");
    }
}

RobotParticipant::~RobotParticipant() {
    if (participant_ != nullptr) {
        participant_->set_listener(nullptr);
        participant_->delete_contained_entities();
        fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
    }
}

fdds::DataReader* RobotParticipant::create_reader(const std::string& topic_name, const std::string& type_name,
                                                  bool keyed, const passthrough::OfferedQos& offer,
                                                  fdds::DataReaderListener* listener) {
    std::lock_guard<std::mutex> lock(mutex_);
    fdds::Topic* topic = passthrough::passthrough_topic(participant_, topic_name, type_name, keyed);
    fdds::Subscriber* subscriber = subscribers_.get(participant_, offer);
    // A topic made here for a reader that could not be made goes again: nothing half-made stays behind.
    const auto drop_unused_topic = [&] {
        if (topic != nullptr && readers_of_topic_.count(topic_name) == 0) {
            participant_->delete_topic(topic);
        }
    };
    if (topic == nullptr || subscriber == nullptr) {
        std::cerr << "telemetry-gateway: cannot create robot topic " << topic_name << " (type " << type_name << ")\n";
        drop_unused_topic();
        return nullptr;
    }

    const fdds::DataReaderQos qos =
        passthrough::passthrough_reader_qos(subscriber->get_default_datareader_qos(), offer, keyed);

    fdds::DataReader* reader = subscriber->create_datareader(topic, qos, listener, fdds::StatusMask::all());
    if (reader == nullptr) {
        std::cerr << "telemetry-gateway: cannot create a reader for " << topic_name << " (" << offer.describe()
                  << ")\n";
        drop_unused_topic();
        return nullptr;
    }
    ++readers_of_topic_[topic_name];
    return reader;
}

void RobotParticipant::delete_reader(fdds::DataReader* reader) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (reader == nullptr) {
        return;
    }
    reader->set_listener(nullptr);
    auto* topic = const_cast<fdds::TopicDescription*>(reader->get_topicdescription());
    const_cast<fdds::Subscriber*>(reader->get_subscriber())->delete_datareader(reader);
    // The topic goes with its last lane's reader.
    if (--readers_of_topic_[topic->get_name()] == 0) {
        readers_of_topic_.erase(topic->get_name());
        if (auto* t = dynamic_cast<fdds::Topic*>(topic)) {
            participant_->delete_topic(t);
        }
    }
}

eprosima::fastrtps::rtps::GuidPrefix_t RobotParticipant::guid_prefix() const {
    return participant_->guid().guidPrefix;
}

}  // namespace tgw::dds
