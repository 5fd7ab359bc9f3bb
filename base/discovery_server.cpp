#include "base/discovery_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>

#include <fastdds/rtps/attributes/ServerAttributes.h>
#include <fastrtps/utils/IPLocator.h>

#include "base/config_error.hpp"

namespace tgw::base {

DiscoveryServerAddress parse_discovery_server(const std::string& text, const std::string& flag) {
    const auto fail = [&](const std::string& why) {
        return ConfigError(flag + " '" + text + "': " + why +
                           " (expected ADDR:PORT, as fastdds discovery -l ADDR -p PORT)");
    };
    const std::size_t colon = text.rfind(':');
    if (colon == std::string::npos) {
        throw fail("no port");
    }
    DiscoveryServerAddress server;
    server.address = text.substr(0, colon);
    in_addr addr{};
    if (inet_pton(AF_INET, server.address.c_str(), &addr) != 1) {
        throw fail("'" + server.address + "' is not an IPv4 address");
    }
    const std::string port = text.substr(colon + 1);
    unsigned long value = 0;
    std::size_t used = 0;
    try {
        value = std::stoul(port, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (port.empty() || used != port.size() || value < 1 || value > 65535) {
        throw fail("the port must be 1 to 65535");
    }
    server.port = static_cast<std::uint16_t>(value);
    return server;
}

void apply_discovery_client(eprosima::fastdds::dds::DomainParticipantQos& qos, const DiscoveryServerAddress& server,
                            DiscoveryRole role) {
    using namespace eprosima::fastdds::rtps;
    using eprosima::fastrtps::rtps::IPLocator;
    using eprosima::fastrtps::rtps::Locator_t;

    RemoteServerAttributes remote;
    get_server_client_default_guidPrefix(0, remote.guidPrefix);
    Locator_t locator;
    locator.kind = LOCATOR_KIND_UDPv4;
    IPLocator::setIPv4(locator, server.address);
    locator.port = server.port;
    remote.metatrafficUnicastLocatorList.push_back(locator);

    auto& discovery = qos.wire_protocol().builtin.discovery_config;
    // A client learns of another's endpoints only where it has one of the same topic; a super client of all.
    discovery.discoveryProtocol = role == DiscoveryRole::super_client
                                      ? eprosima::fastrtps::rtps::DiscoveryProtocol::SUPER_CLIENT
                                      : eprosima::fastrtps::rtps::DiscoveryProtocol::CLIENT;
    discovery.m_DiscoveryServers.clear();
    discovery.m_DiscoveryServers.push_back(remote);
    qos.wire_protocol().builtin.initialPeersList.clear();
}

}  // namespace tgw::base
