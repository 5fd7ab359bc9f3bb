// A Fast DDS Discovery Server on the WAN (telemetry-gateway --wan-discovery-server, tm-basecamp
// --discovery-server): participants announce themselves to the server alone, and learn from it whom to talk to,
// instead of announcing themselves to every peer. A fleet's robots then need not know each other, and one that
// joins or leaves costs the others nothing but the server's word.
#pragma once

#include <cstdint>
#include <string>

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

namespace tgw::base {

/// Where the server listens: `fastdds discovery -i 0 -l ADDRESS -p PORT` (Debian's fastdds-tools).
struct DiscoveryServerAddress {
    std::string address;  ///< dotted IPv4
    std::uint16_t port = 0;
};

/// Parses "ADDR:PORT" (IPv4, port 1 to 65535). Throws ConfigError naming `flag` and the value.
DiscoveryServerAddress parse_discovery_server(const std::string& text, const std::string& flag);

/// What a client hears from the server.
enum class DiscoveryRole {
    /// Of the endpoints of the topics it has endpoints of: a gateway, a robot publisher.
    client,
    /// Of every endpoint: a base-camp tool that subscribes to whatever it discovers (record, relay, stats).
    super_client,
};

/// Makes `qos`'s participant a client of `server` in `role`: its discovery goes through the server alone, which
/// it knows by server id 0's GUID prefix, as `fastdds discovery -i 0` and ROS 2's ROS_DISCOVERY_SERVER have it.
/// Its initial peers are cleared: the server tells it of the others.
void apply_discovery_client(eprosima::fastdds::dds::DomainParticipantQos& qos, const DiscoveryServerAddress& server,
                            DiscoveryRole role);

}  // namespace tgw::base
