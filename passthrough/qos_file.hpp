#pragma once

#include <optional>
#include <string>
#include <vector>

#include <fastdds/dds/publisher/qos/WriterQos.hpp>

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include "base/time.hpp"

namespace tgw::passthrough {

/// Participant profiles the gateway starts from when the --qos file defines them; transports, locators and
/// discovery peers are always set by the gateway on top.
inline constexpr const char* ROBOT_PARTICIPANT_PROFILE = "tgw_robot_participant";
inline constexpr const char* WAN_PARTICIPANT_PROFILE = "tgw_wan_participant";

/// Loads a Fast DDS XML profiles file into the process (DomainParticipantFactory::load_XML_profiles_file).
/// Throws base::ConfigError naming the file, and the line for malformed XML, when it does not load.
void load_qos_file(const std::string& path);

/// The Lifespan of the data_writer profile named `topic` in the loaded files: the operator's TTL for the topic
/// (docs/design.md §4). nullopt when there is no such profile or it sets no finite Lifespan. Needs no participant.
std::optional<base::Duration> writer_profile_lifespan(const std::string& topic);

/// A topic the --qos file names with its type (a data_writer profile whose <topic> has a <dataType>): the
/// gateway bridges it at start-up, before any publisher appears, so its WAN writer's announcement has crossed
/// the link by the time the first samples come.
struct DeclaredTopic {
    std::string topic;
    std::string type_name;
    bool keyed = false;
    std::optional<base::Duration> lifespan;
    eprosima::fastdds::dds::WriterQos qos;  ///< the profile's: what the early lane's reader asks for
};

/// The declared topics of a loaded --qos file, in file order. Throws base::ConfigError naming the file and
/// line of a data_writer profile whose <topic> names another topic than its profile_name.
std::vector<DeclaredTopic> declared_topics(const std::string& path);

/// The participant profile `name` from the loaded files, if there is one.
std::optional<eprosima::fastdds::dds::DomainParticipantQos> participant_profile(const std::string& name);

}  // namespace tgw::passthrough
