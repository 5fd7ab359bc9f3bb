// The WAN participant's UDPv4 transport, with its sends passed through a DatagramCoalescer.
#pragma once

#include <memory>

#include <fastdds/rtps/transport/ChainingTransport.h>
#include <fastdds/rtps/transport/ChainingTransportDescriptor.h>

#include "gateway/dds/datagram_coalescer.hpp"

namespace tgw::dds {

/// Put in a participant's user_transports in place of `low_level`: Fast DDS creates a CoalescingTransport from
/// it, which sends through `coalescer`. The coalescer must outlive the participant, and be stopped before the
/// participant is deleted.
struct CoalescingTransportDescriptor : public eprosima::fastdds::rtps::ChainingTransportDescriptor {
    CoalescingTransportDescriptor(std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface> low_level,
                                  std::shared_ptr<DatagramCoalescer> coalescer);

    eprosima::fastdds::rtps::TransportInterface* create_transport() const override;

    std::shared_ptr<DatagramCoalescer> coalescer;
};

/// Receives as the low-level transport does; hands every outgoing RTPS message to the coalescer.
class CoalescingTransport final : public eprosima::fastdds::rtps::ChainingTransport, public DatagramSender {
  public:
    explicit CoalescingTransport(const CoalescingTransportDescriptor& descriptor);

    bool send(eprosima::fastrtps::rtps::SenderResource* low_sender_resource,
              const eprosima::fastrtps::rtps::octet* send_buffer, std::uint32_t send_buffer_size,
              eprosima::fastrtps::rtps::LocatorsIterator* destination_locators_begin,
              eprosima::fastrtps::rtps::LocatorsIterator* destination_locators_end,
              const std::chrono::steady_clock::time_point& timeout) override;

    void receive(eprosima::fastdds::rtps::TransportReceiverInterface* next_receiver,
                 const eprosima::fastrtps::rtps::octet* receive_buffer, std::uint32_t receive_buffer_size,
                 const eprosima::fastrtps::rtps::Locator_t& local_locator,
                 const eprosima::fastrtps::rtps::Locator_t& remote_locator) override;

    bool send_datagram(const DatagramDestination& destination, const std::uint8_t* bytes, std::size_t size) override;

    eprosima::fastdds::rtps::TransportDescriptorInterface* get_configuration() override { return &descriptor_; }

  private:
    CoalescingTransportDescriptor descriptor_;
    std::shared_ptr<DatagramCoalescer> coalescer_;
};

}  // namespace tgw::dds
