// A fleet's robots kept apart on the WAN (telemetry-gateway --robot-name): each robot's topics appear at the base
// camp under the robot's name, where a ROS 2 namespace would put them.
#pragma once

#include <string>
#include <string_view>

namespace tgw::base {

/// Why `name` cannot name a robot, or empty when it can. A robot name is one ROS 2 namespace token (letters,
/// digits and underscores, not starting with a digit, at most 64 characters), so that `rt/NAME/...` is a valid
/// ROS 2 topic and `NAME/...` a valid DDS topic name.
std::string robot_name_problem(std::string_view name);

/// `topic` as robot `robot` publishes it on the WAN. ROS 2 topics and services (the DDS prefixes rt/, rq/, rr/)
/// get the name after their prefix, as `ros2 run ... --ros-args -r __ns:=/NAME` would give: rt/chatter ->
/// rt/NAME/chatter. Any other topic gets it in front: telemetry/A -> NAME/telemetry/A. An empty `robot` leaves
/// `topic` as it is.
std::string namespaced_topic(std::string_view robot, std::string_view topic);

}  // namespace tgw::base
