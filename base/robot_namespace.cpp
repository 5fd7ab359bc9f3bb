#include "base/robot_namespace.hpp"

#include <array>

namespace tgw::base {

namespace {

constexpr std::size_t MAX_ROBOT_NAME = 64;

bool is_letter(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}
bool is_digit(char c) {
    return c >= '0' && c <= '9';
}

}  // namespace

std::string robot_name_problem(std::string_view name) {
    if (name.empty()) {
        return "is empty";
    }
    if (name.size() > MAX_ROBOT_NAME) {
        return "is longer than " + std::to_string(MAX_ROBOT_NAME) + " characters";
    }
    if (is_digit(name.front())) {
        return "starts with a digit";
    }
    for (const char c : name) {
        if (!is_letter(c) && !is_digit(c) && c != '_') {
            return std::string("holds '") + c + "': only letters, digits and '_' (a ROS 2 namespace token)";
        }
    }
    return {};
}

std::string namespaced_topic(std::string_view robot, std::string_view topic) {
    if (robot.empty()) {
        return std::string(topic);
    }
    // ROS 2's DDS prefixes: topics, service requests, service replies.
    constexpr std::array<std::string_view, 3> ROS2_PREFIXES = {"rt/", "rq/", "rr/"};
    for (const std::string_view prefix : ROS2_PREFIXES) {
        if (topic.size() > prefix.size() && topic.substr(0, prefix.size()) == prefix) {
            return std::string(prefix).append(robot).append("/").append(topic.substr(prefix.size()));
        }
    }
    return std::string(robot).append("/").append(topic);
}

}  // namespace tgw::base
