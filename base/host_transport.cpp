#include "base/host_transport.hpp"

#include <algorithm>
#include <memory>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>

#include "base/interface_addresses.hpp"
#include "base/loopback_transport.hpp"
#include "base/peer_transport.hpp"

namespace tgw::base {

namespace {

constexpr const char* DEFAULT_MULTICAST_GROUP = "239.255.0.1";

}  // namespace

void apply_host_transport(eprosima::fastdds::dds::DomainParticipantQos& qos, int domain,
                          const HostTransport& transport) {
    const auto& addresses = transport.addresses;
    const bool on_loopback = addresses.empty() || std::any_of(addresses.begin(), addresses.end(), is_loopback_ipv4);
    const bool off_loopback = addresses.empty() || !std::all_of(addresses.begin(), addresses.end(), is_loopback_ipv4);

    auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
    udp->interfaceWhiteList = addresses;
    udp->receiveBufferSize = transport.receive_buffer_bytes;

    // Initial peers from the profile stand; else announcements go where the host's processes listen.
    auto& peers = qos.wire_protocol().builtin.initialPeersList;
    if (peers.empty()) {
        if (on_loopback) {
            peers.push_back(udp_locator("127.0.0.1", 0));  // port 0: one per index, up to maxInitialPeersRange
            udp->maxInitialPeersRange = PARTICIPANT_INDEXES;
        }
        // Initial peers replace Fast DDS's multicast default: kept where an interface may carry it.
        if (off_loopback) {
            const auto port = qos.wire_protocol().port.getMulticastPort(static_cast<std::uint32_t>(domain));
            peers.push_back(udp_locator(DEFAULT_MULTICAST_GROUP, port));
        }
    }

    qos.transport().use_builtin_transports = false;
    if (transport.shm)
        qos.transport().user_transports.push_back(
            std::make_shared<eprosima::fastdds::rtps::SharedMemTransportDescriptor>());
    if (!addresses.empty() && on_loopback)
        qos.transport().user_transports.push_back(std::make_shared<LoopbackTransportDescriptor>(udp));
    else
        qos.transport().user_transports.push_back(udp);  // on every interface, Fast DDS answers on loopback itself
}

}  // namespace tgw::base
