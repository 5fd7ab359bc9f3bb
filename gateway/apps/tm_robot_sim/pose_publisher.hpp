// The robot's pose (tgw::idl::RobotPose) along the survey route, published as a robot's localisation would: in a
// thread of its own, beside the telemetry workload.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "base/peer_transport.hpp"
#include "base/time.hpp"

namespace eprosima::fastdds::dds {
class DataWriter;
class DomainParticipant;
}  // namespace eprosima::fastdds::dds

namespace tgw::robot_sim {

class PosePublisher {
  public:
    /// A participant of its own on `domain` and a writer of `topic` (TTL `ttl`, as the Lifespan). Throws
    /// base::ConfigError when DDS refuses them.
    PosePublisher(int domain, const std::string& topic, double rate_hz, base::Duration ttl,
                  const base::PeerTransport& transport);
    /// Stops publishing and deletes the participant.
    ~PosePublisher();
    PosePublisher(const PosePublisher&) = delete;
    PosePublisher& operator=(const PosePublisher&) = delete;

    /// Publishes survey_pose(seconds since start()) at the rate until the destructor or `stop`.
    void start(const std::atomic<bool>& stop);

    std::uint64_t published() const { return published_.load(); }

  private:
    const double rate_hz_;
    eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
    eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
    std::atomic<bool> stopping_{false};
    std::atomic<std::uint64_t> published_{0};
    std::thread thread_;
};

}  // namespace tgw::robot_sim
