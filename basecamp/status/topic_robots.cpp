#include "basecamp/status/topic_robots.hpp"

#include "basecamp/status/gateway_status.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {

void TopicRobots::add(SampleRecord sample) {
    if (sample.topic != wire::STATUS_TOPIC) {
        return;
    }
    if (const std::optional<idl::GatewayStatus> status = decode_gateway_status(sample.payload)) {
        take(*status);
    }
}

void TopicRobots::take(const idl::GatewayStatus& status) {
    if (status.robot_name().empty()) {
        return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    for (const idl::TopicStatus& topic : status.topics()) {
        robot_by_topic_[topic.name()] = status.robot_name();
    }
}

std::string TopicRobots::robot_of(const std::string& topic) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = robot_by_topic_.find(topic);
    return it == robot_by_topic_.end() ? std::string() : it->second;
}

bool TopicRobots::any() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return !robot_by_topic_.empty();
}

}  // namespace tgw::basecamp
