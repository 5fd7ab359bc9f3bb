// The base camp's participant on a domain it listens to, as the recorder and echo make it.
#pragma once

#include <optional>
#include <string>

#include "base/peer_transport.hpp"
#include "base/security_files.hpp"
#include "passthrough/discovery.hpp"

namespace eprosima::fastdds::dds {
class DomainParticipant;
}  // namespace eprosima::fastdds::dds

namespace tgw::basecamp {

/// A participant named `name` on `domain` over `transport` (with DDS Security when `security` is given) whose
/// discovery goes to `discovery`, which ignores the participant's own endpoints. The caller deletes it. Throws
/// base::ConfigError naming --domain when Fast DDS refuses it.
eprosima::fastdds::dds::DomainParticipant* create_camp_participant(int domain, const base::PeerTransport& transport,
                                                                   const std::optional<base::SecurityFiles>& security,
                                                                   const std::string& name,
                                                                   passthrough::Discovery& discovery);

}  // namespace tgw::basecamp
