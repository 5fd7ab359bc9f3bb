// The relay's WAN transport when it measures the channel (tm-basecamp relay --measure-channel): it receives as
// the UDP transport below it does, and shows every datagram to a meter on the way in.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>

#include <fastdds/rtps/transport/ChainingTransport.h>
#include <fastdds/rtps/transport/ChainingTransportDescriptor.h>

namespace tgw::basecamp {

/// Called with each datagram received and the address it came from (Locator_t::address), in Fast DDS's receive
/// threads, before the participant reads it.
using DatagramMeter =
    std::function<void(const std::uint8_t* bytes, std::size_t size, const std::array<std::uint8_t, 16>& from)>;

/// Put in a participant's user_transports in place of `low_level`: Fast DDS creates a MeteredTransport from it.
struct MeteredTransportDescriptor : public eprosima::fastdds::rtps::ChainingTransportDescriptor {
    MeteredTransportDescriptor(std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface> low_level,
                               DatagramMeter meter);

    eprosima::fastdds::rtps::TransportInterface* create_transport() const override;

    DatagramMeter meter;
};

/// Sends and receives as the low-level transport does; shows each received datagram to the descriptor's meter.
class MeteredTransport final : public eprosima::fastdds::rtps::ChainingTransport {
  public:
    explicit MeteredTransport(const MeteredTransportDescriptor& descriptor);

    bool send(eprosima::fastrtps::rtps::SenderResource* low_sender_resource,
              const eprosima::fastrtps::rtps::octet* send_buffer, std::uint32_t send_buffer_size,
              eprosima::fastrtps::rtps::LocatorsIterator* destination_locators_begin,
              eprosima::fastrtps::rtps::LocatorsIterator* destination_locators_end,
              const std::chrono::steady_clock::time_point& timeout) override;

    void receive(eprosima::fastdds::rtps::TransportReceiverInterface* next_receiver,
                 const eprosima::fastrtps::rtps::octet* receive_buffer, std::uint32_t receive_buffer_size,
                 const eprosima::fastrtps::rtps::Locator_t& local_locator,
                 const eprosima::fastrtps::rtps::Locator_t& remote_locator) override;

    eprosima::fastdds::rtps::TransportDescriptorInterface* get_configuration() override { return &descriptor_; }

  private:
    MeteredTransportDescriptor descriptor_;
};

}  // namespace tgw::basecamp
