// Which robot of a fleet each topic at the base camp comes from. A gateway's status (tgw/status) carries its
// --robot-name and every topic it bridges under the base camp's name, so the answer comes from the gateway that
// bridges the topic, not from guessing at the topic's name (`telemetry/A` of an unnamed robot and
// `rover1/telemetry/A` look alike to a parser).
#pragma once

#include <algorithm>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "GatewayStatus.h"
#include "basecamp/sample/sample_consumer.hpp"

namespace tgw::basecamp {

/// Learns from the status samples among those it is given; other samples and undecodable statuses are ignored.
/// Thread-safe.
class TopicRobots final : public SampleConsumer {
  public:
    void add_topic(TopicRecord /*topic*/) override {}
    void add(SampleRecord sample) override;

    void take(const idl::GatewayStatus& status);

    /// The robot whose gateway bridges `topic`, or empty when no status of a named robot has named the topic.
    std::string robot_of(const std::string& topic) const;
    /// Whether any status named a robot.
    bool any() const;

  private:
    mutable std::mutex mutex_;
    std::map<std::string, std::string> robot_by_topic_;
};

/// Whether a table of `rows` (each with a `robot`) gets a robot column: only for a fleet, so that a single unnamed
/// robot's table keeps its shape for scripts.
template <typename Row>
bool has_robot_column(const std::vector<Row>& rows) {
    return std::any_of(rows.begin(), rows.end(), [](const Row& r) { return !r.robot.empty(); });
}

/// A robot column's cell: the robot, or "-" when there is none.
inline std::string robot_cell(const std::string& robot) {
    return robot.empty() ? std::string("-") : robot;
}

}  // namespace tgw::basecamp
