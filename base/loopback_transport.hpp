// A UDPv4 transport on loopback that still reaches the processes of this host announcing their other addresses.
#pragma once

#include <memory>

#include <fastdds/rtps/transport/ChainingTransport.h>
#include <fastdds/rtps/transport/ChainingTransportDescriptor.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>

namespace tgw::base {

/// Put in a participant's user_transports in place of a UDPv4 transport whose interfaces include 127.0.0.1 but
/// not every address of the host.
///
/// A Fast DDS process with its defaults announces the addresses of its host's other interfaces (the robot's LAN,
/// the radio), not 127.0.0.1. A UDPv4 transport limited to some interfaces refuses an address of this host it
/// may not use, so it never answers that process: the two then find each other over shared memory or not at
/// all, and not at all when they run as different users. This transport sends to such an address on 127.0.0.1,
/// same port, where the process listens too (Fast DDS binds the any-address), so the participant stays off the
/// interfaces it was kept from (the radio) and still reaches every process of its host over UDP.
struct LoopbackTransportDescriptor : public eprosima::fastdds::rtps::ChainingTransportDescriptor {
    explicit LoopbackTransportDescriptor(std::shared_ptr<eprosima::fastdds::rtps::UDPv4TransportDescriptor> udp);

    eprosima::fastdds::rtps::TransportInterface* create_transport() const override;
};

class LoopbackTransport : public eprosima::fastdds::rtps::ChainingTransport {
  public:
    explicit LoopbackTransport(const LoopbackTransportDescriptor& descriptor);

    /// An address of this host (other than loopback) becomes 127.0.0.1; the rest as the low-level transport says.
    bool transform_remote_locator(const eprosima::fastrtps::rtps::Locator_t& remote,
                                  eprosima::fastrtps::rtps::Locator_t& result) const override;

    bool send(eprosima::fastrtps::rtps::SenderResource* low_sender_resource,
              const eprosima::fastrtps::rtps::octet* send_buffer, uint32_t send_buffer_size,
              eprosima::fastrtps::rtps::LocatorsIterator* destination_locators_begin,
              eprosima::fastrtps::rtps::LocatorsIterator* destination_locators_end,
              const std::chrono::steady_clock::time_point& timeout) override;

    void receive(eprosima::fastdds::rtps::TransportReceiverInterface* next_receiver,
                 const eprosima::fastrtps::rtps::octet* receive_buffer, uint32_t receive_buffer_size,
                 const eprosima::fastrtps::rtps::Locator_t& local_locator,
                 const eprosima::fastrtps::rtps::Locator_t& remote_locator) override;

    eprosima::fastdds::rtps::TransportDescriptorInterface* get_configuration() override { return &descriptor_; }

  private:
    LoopbackTransportDescriptor descriptor_;
};

}  // namespace tgw::base
