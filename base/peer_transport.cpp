#include "base/peer_transport.hpp"

#include <memory>
#include <optional>
#include <vector>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include "base/config_error.hpp"
#include "base/discovery_server.hpp"
#include "base/interface_addresses.hpp"

namespace tgw::base {

namespace {

using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;

}  // namespace

Locator_t udp_locator(const std::string& address, std::uint32_t port) {
    Locator_t locator;
    locator.kind = LOCATOR_KIND_UDPv4;
    IPLocator::setIPv4(locator, address);
    locator.port = port;
    return locator;
}

std::string resolve_ipv4(const std::string& name_or_addr, const std::string& flag) {
    if (is_ipv4(name_or_addr))
        return name_or_addr;
    const auto addresses = interface_addresses();
    if (!addresses)
        throw ConfigError(flag + ": cannot list network interfaces");
    for (const InterfaceAddress& each : *addresses) {
        if (each.interface == name_or_addr)
            return each.address;
    }
    throw ConfigError(flag + ": '" + name_or_addr + "' is neither an IPv4 address nor an interface with one");
}

std::vector<std::string> resolve_peers(const PeerTransport& transport) {
    std::vector<std::string> addresses;
    for (const std::string& peer : transport.peers) {
        if (!is_ipv4(peer) && !is_host_name(peer))
            throw ConfigError(transport.peers_flag + ": '" + peer + "' is neither an IPv4 address nor a host name");
        const std::optional<std::string> address = lookup_ipv4(peer);
        if (!address)
            throw ConfigError(transport.peers_flag + ": '" + peer + "' does not resolve to an IPv4 address (now)");
        addresses.push_back(*address);
    }
    return addresses;
}

void apply_peer_transport(eprosima::fastdds::dds::DomainParticipantQos& qos, const PeerTransport& transport,
                          int domain) {
    using eprosima::fastdds::rtps::SharedMemTransportDescriptor;
    using eprosima::fastdds::rtps::UDPv4TransportDescriptor;
    const bool remote = !transport.peers.empty() || !transport.discovery_server.empty();
    if (!remote && transport.interface.empty()) {
        // Fast DDS's builtin UDP transport takes its receive buffer from here.
        qos.transport().listen_socket_buffer_size = transport.receive_buffer_bytes;
        return;
    }
    if (!transport.peers.empty() && !transport.discovery_server.empty())
        throw ConfigError(transport.discovery_server_flag + " excludes " + transport.peers_flag +
                          ": the server tells each participant of the others");

    std::optional<DiscoveryServerAddress> server;
    if (!transport.discovery_server.empty())
        server = parse_discovery_server(transport.discovery_server, transport.discovery_server_flag);

    auto udp = std::make_shared<UDPv4TransportDescriptor>();
    udp->receiveBufferSize = transport.receive_buffer_bytes;
    std::string bound;
    if (!transport.interface.empty()) {
        bound = resolve_ipv4(transport.interface, transport.interface_flag);
        // Over the link, the locators below bind it to the address. A whitelist would be checked against the
        // interfaces up at start, once: a program started before its radio is up would keep none for its life.
        if (!remote)
            udp->interfaceWhiteList.push_back(bound);
    }
    qos.transport().use_builtin_transports = false;
    qos.transport().user_transports.push_back(udp);

    auto& builtin = qos.wire_protocol().builtin;
    if (!remote) {
        // Local use (the robot domain): multicast discovery on the bound interface, shared memory kept.
        qos.transport().user_transports.push_back(std::make_shared<SharedMemTransportDescriptor>());
        return;
    }

    // Over the slow link: the peer runs one participant per domain, so its first port is enough; every
    // SPDP datagram to a port nobody listens on costs link time for nothing. On this host, the gateway need not
    // be the domain's first participant (a recorder started before it takes that port), and then it would hear
    // of us only at its next periodic announcement, 20 s later.
    udp->maxInitialPeersRange = 1;
    for (const std::string& peer : resolve_peers(transport)) {
        if (!is_loopback_ipv4(peer)) {
            builtin.initialPeersList.push_back(udp_locator(peer));
            continue;
        }
        for (int id = 0; id < SAME_HOST_PEER_PARTICIPANTS; ++id)
            builtin.initialPeersList.push_back(udp_locator(peer, metatraffic_unicast_port(domain, id)));
    }
    if (server)
        apply_discovery_client(qos, *server, transport.discovery_role);
    // Naming a unicast metatraffic locator keeps Fast DDS from adding its default multicast ones; port 0
    // lets it pick the participant's standard port.
    const std::string local = bound.empty() ? std::string("0.0.0.0") : bound;
    builtin.metatrafficUnicastLocatorList.push_back(udp_locator(local));
    qos.wire_protocol().default_unicast_locator_list.push_back(udp_locator(local));
    // SPDP announcements are about 500 bytes each: every 3 s (the default) is 1,300 bit/s per peer on a link
    // that may carry 10,000. Announce every 10 s and keep the lease well above it.
    builtin.discovery_config.leaseDuration = eprosima::fastrtps::Duration_t(60, 0);
    builtin.discovery_config.leaseDuration_announcementperiod = eprosima::fastrtps::Duration_t(10, 0);
}

}  // namespace tgw::base
