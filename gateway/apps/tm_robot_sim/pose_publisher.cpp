#include "gateway/apps/tm_robot_sim/pose_publisher.hpp"

#include <chrono>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>

#include "RobotPosePubSubTypes.h"
#include "base/config_error.hpp"
#include "gateway/apps/tm_robot_sim/survey_route.hpp"

namespace tgw::robot_sim {

namespace dds = eprosima::fastdds::dds;

PosePublisher::PosePublisher(int domain, const std::string& topic, double rate_hz, base::Duration ttl,
                             const base::PeerTransport& transport)
    : rate_hz_(rate_hz) {
    auto* factory = dds::DomainParticipantFactory::get_instance();
    dds::DomainParticipantQos qos = factory->get_default_participant_qos();
    qos.name("tm-robot-sim/pose");
    base::apply_peer_transport(qos, transport, domain);
    participant_ = factory->create_participant(domain, qos);
    if (participant_ == nullptr)
        throw base::ConfigError("--domain: cannot create a DDS participant on domain " + std::to_string(domain));
    dds::TypeSupport type(new idl::RobotPosePubSubType());
    dds::Topic* pose_topic = type.register_type(participant_) == ReturnCode_t::RETCODE_OK
                                 ? participant_->create_topic(topic, type.get_type_name(), dds::TOPIC_QOS_DEFAULT)
                                 : nullptr;
    dds::Publisher* publisher = participant_->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
    if (pose_topic == nullptr || publisher == nullptr)
        throw base::ConfigError("--pose: cannot create topic '" + topic + "'");
    dds::DataWriterQos wqos = publisher->get_default_datawriter_qos();
    // What a localisation node offers: the latest pose, best effort; stale ones expire.
    wqos.reliability().kind = dds::BEST_EFFORT_RELIABILITY_QOS;
    wqos.history().kind = dds::KEEP_LAST_HISTORY_QOS;
    wqos.history().depth = 1;
    const auto ns = ttl.count();
    wqos.lifespan().duration = eprosima::fastrtps::Duration_t(static_cast<int32_t>(ns / 1'000'000'000),
                                                              static_cast<uint32_t>(ns % 1'000'000'000));
    wqos.data_sharing().off();
    writer_ = publisher->create_datawriter(pose_topic, wqos);
    if (writer_ == nullptr)
        throw base::ConfigError("--pose: cannot create a DDS writer for '" + topic + "'");
}

PosePublisher::~PosePublisher() {
    stopping_.store(true);
    if (thread_.joinable())
        thread_.join();
    participant_->delete_contained_entities();
    dds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

void PosePublisher::start(const std::atomic<bool>& stop) {
    thread_ = std::thread([this, &stop] {
        const auto start = base::SteadyClock::now();
        const auto period = base::from_seconds(1.0 / rate_hz_);
        auto next = start;
        while (!stopping_.load() && !stop.load()) {
            const Pose pose = survey_pose(base::to_seconds(next - start));
            idl::RobotPose sample;
            sample.x(pose.x);
            sample.y(pose.y);
            sample.heading_rad(pose.heading_rad);
            if (writer_->write(&sample))
                published_.fetch_add(1);
            next += period;
            std::this_thread::sleep_until(next);
        }
    });
}

}  // namespace tgw::robot_sim
