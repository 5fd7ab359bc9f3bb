#include "basecamp/relay/metered_transport.hpp"

#include <algorithm>
#include <iterator>
#include <utility>

#include <fastdds/rtps/network/SenderResource.h>

namespace tgw::basecamp {

namespace rtps = eprosima::fastrtps::rtps;

MeteredTransportDescriptor::MeteredTransportDescriptor(
    std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface> low_level, DatagramMeter meter_in)
    : ChainingTransportDescriptor(std::move(low_level)), meter(std::move(meter_in)) {}

eprosima::fastdds::rtps::TransportInterface* MeteredTransportDescriptor::create_transport() const {
    return new MeteredTransport(*this);
}

MeteredTransport::MeteredTransport(const MeteredTransportDescriptor& descriptor)
    : ChainingTransport(descriptor), descriptor_(descriptor) {}

bool MeteredTransport::send(rtps::SenderResource* low_sender_resource, const rtps::octet* send_buffer,
                            std::uint32_t send_buffer_size, rtps::LocatorsIterator* destination_locators_begin,
                            rtps::LocatorsIterator* destination_locators_end,
                            const std::chrono::steady_clock::time_point& timeout) {
    return low_sender_resource->send(send_buffer, send_buffer_size, destination_locators_begin,
                                     destination_locators_end, timeout);
}

void MeteredTransport::receive(eprosima::fastdds::rtps::TransportReceiverInterface* next_receiver,
                               const rtps::octet* receive_buffer, std::uint32_t receive_buffer_size,
                               const rtps::Locator_t& local_locator, const rtps::Locator_t& remote_locator) {
    if (descriptor_.meter) {
        std::array<std::uint8_t, 16> from;
        std::copy(std::begin(remote_locator.address), std::end(remote_locator.address), from.begin());
        descriptor_.meter(receive_buffer, receive_buffer_size, from);
    }
    next_receiver->OnDataReceived(receive_buffer, receive_buffer_size, local_locator, remote_locator);
}

}  // namespace tgw::basecamp
