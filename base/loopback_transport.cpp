#include "base/loopback_transport.hpp"

#include <algorithm>
#include <utility>

#include <fastdds/rtps/network/SenderResource.h>
#include <fastrtps/utils/IPLocator.h>

#include "base/interface_addresses.hpp"

namespace tgw::base {

namespace rtps = eprosima::fastrtps::rtps;

namespace {

/// True if `locator` is a UDPv4 locator holding one of this host's interfaces' addresses now.
bool is_address_of_this_host(const rtps::Locator_t& locator) {
    if (locator.kind != LOCATOR_KIND_UDPv4)
        return false;
    const auto host = interface_addresses();
    if (!host)
        return false;
    const std::string address = rtps::IPLocator::toIPv4string(locator);
    return std::any_of(host->begin(), host->end(),
                       [&](const InterfaceAddress& each) { return each.address == address; });
}

}  // namespace

LoopbackTransportDescriptor::LoopbackTransportDescriptor(
    std::shared_ptr<eprosima::fastdds::rtps::UDPv4TransportDescriptor> udp)
    : ChainingTransportDescriptor(std::move(udp)) {}

eprosima::fastdds::rtps::TransportInterface* LoopbackTransportDescriptor::create_transport() const {
    return new LoopbackTransport(*this);
}

LoopbackTransport::LoopbackTransport(const LoopbackTransportDescriptor& descriptor)
    : ChainingTransport(descriptor), descriptor_(descriptor) {}

bool LoopbackTransport::transform_remote_locator(const rtps::Locator_t& remote, rtps::Locator_t& result) const {
    // Asked of the host now, not of the low-level transport: it knows the addresses up when it started, and a
    // radio's address may come later.
    if (!rtps::IPLocator::isLocal(remote) && is_address_of_this_host(remote)) {
        result = remote;
        rtps::IPLocator::setIPv4(result, 127, 0, 0, 1);
        return true;
    }
    return ChainingTransport::transform_remote_locator(remote, result);
}

bool LoopbackTransport::send(rtps::SenderResource* low_sender_resource, const rtps::octet* send_buffer,
                             uint32_t send_buffer_size, rtps::LocatorsIterator* destination_locators_begin,
                             rtps::LocatorsIterator* destination_locators_end,
                             const std::chrono::steady_clock::time_point& timeout) {
    return low_sender_resource->send(send_buffer, send_buffer_size, destination_locators_begin,
                                     destination_locators_end, timeout);
}

void LoopbackTransport::receive(eprosima::fastdds::rtps::TransportReceiverInterface* next_receiver,
                                const rtps::octet* receive_buffer, uint32_t receive_buffer_size,
                                const rtps::Locator_t& local_locator, const rtps::Locator_t& remote_locator) {
    next_receiver->OnDataReceived(receive_buffer, receive_buffer_size, local_locator, remote_locator);
}

}  // namespace tgw::base
