// The WAN participant's UDPv4 transport, with its sends passed through a DatagramCoalescer.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include <fastdds/rtps/transport/ChainingTransport.h>
#include <fastdds/rtps/transport/ChainingTransportDescriptor.h>

#include "gateway/dds/datagram_coalescer.hpp"
#include "gateway/dds/repair_desk.hpp"
#include "gateway/dds/repeat_throttle.hpp"

namespace tgw::dds {

/// Called with the bytes (whole Ethernet frames) of what the participant sends that no scheduled write
/// accounts for: discovery, heartbeats, acknowledgements, repairs, history sent to a late joiner, and the
/// further copies of a sample sent to several readers. Runs in Fast DDS's sending threads.
/// The WAN's default bytes between a reliable writer's piggy-backed HEARTBEATs (WanConfig::heartbeat_spacing_bytes).
constexpr std::uint32_t DEFAULT_HEARTBEAT_SPACING_BYTES = 1024;

using UnscheduledTrafficCallback = std::function<void(std::uint64_t frame_bytes)>;

/// Put in a participant's user_transports in place of `low_level`: Fast DDS creates a CoalescingTransport from
/// it, which sends through `coalescer`. The coalescer must outlive the participant, and be stopped before the
/// participant is deleted.
struct CoalescingTransportDescriptor : public eprosima::fastdds::rtps::ChainingTransportDescriptor {
    CoalescingTransportDescriptor(std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface> low_level,
                                  std::shared_ptr<DatagramCoalescer> coalescer,
                                  UnscheduledTrafficCallback on_unscheduled = {},
                                  std::shared_ptr<RepeatThrottle> repeat_throttle = {});

    eprosima::fastdds::rtps::TransportInterface* create_transport() const override;

    /// Fast DDS 2.9 takes the smallest min_send_buffer_size of a participant's transports as the bytes a
    /// reliable writer sends between piggy-backed HEARTBEATs, and nothing else (the socket's buffer is the
    /// low-level transport's own). 0 (the UDP descriptor's default) puts one in every message.
    std::uint32_t min_send_buffer_size() const override { return heartbeat_spacing_bytes; }

    std::uint32_t heartbeat_spacing_bytes = 0;
    /// Leave out the statistics submessage at the end of each message (RtpsDatagram::statistics_trailer_bytes).
    bool strip_statistics = false;
    /// Leave it out of each message that carries no application's sample (RtpsDatagram::Strippable::
    /// carries_user_sample): a lone HEARTBEAT, ACKNACK or GAP, discovery. A base camp's channel meter reads the
    /// send stamp off the samples' datagrams; Fast DDS counts only the datagrams that carry one.
    bool strip_statistics_without_samples = false;
    /// Leave out the INFO_DST a message to one participant's unicast locators starts with
    /// (RtpsDatagram::leading_destination_bytes).
    bool strip_destination = false;
    /// Leave out the INFO_TS of a message that carries one sample written inside an UnstampedWrite
    /// (RtpsDatagram::Strippable::timestamp_bytes).
    bool strip_timestamp = false;
    /// Leave out the HEARTBEAT of a message whose fragment does not end its sample (without_early_heartbeats).
    bool strip_early_heartbeats = false;
    /// Send through the low-level transport's first output socket alone. Fast DDS 2.9's UDPv4 transport without
    /// an interface whitelist opens a socket on every address for unicast, then one more per interface for
    /// multicast alone, and hands each message to each: the ones after the first send no unicast message and
    /// report it failed, while every copy would be counted here. For a participant that sends no multicast.
    bool first_output_socket_only = false;
    std::shared_ptr<DatagramCoalescer> coalescer;
    UnscheduledTrafficCallback on_unscheduled;
    /// Holds back repeated HEARTBEATs and ACKNACKs; none: every message goes.
    std::shared_ptr<RepeatThrottle> repeat_throttle;
    /// Takes the repairs of scheduled samples for the schedule; none: they go at once, charged as unscheduled.
    std::shared_ptr<RepairDesk> repair_desk;
};

/// Receives as the low-level transport does; hands every outgoing RTPS message to the coalescer, but a repeat
/// the descriptor's throttle holds back. A message sent outside a write's DatagramCoalescer::DeferScope (and
/// every copy of a write's message after the first, and the HEARTBEAT in a write's message) is reported to the
/// descriptor's on_unscheduled.
class CoalescingTransport final : public eprosima::fastdds::rtps::ChainingTransport, public DatagramSender {
  public:
    explicit CoalescingTransport(const CoalescingTransportDescriptor& descriptor);
    /// Sends what the coalescer keeps for it and drops the repairs held for it, while its channels still exist.
    ~CoalescingTransport() override;

    bool send(eprosima::fastrtps::rtps::SenderResource* low_sender_resource,
              const eprosima::fastrtps::rtps::octet* send_buffer, std::uint32_t send_buffer_size,
              eprosima::fastrtps::rtps::LocatorsIterator* destination_locators_begin,
              eprosima::fastrtps::rtps::LocatorsIterator* destination_locators_end,
              const std::chrono::steady_clock::time_point& timeout) override;

    /// As ChainingTransport's, keeping only the first new socket with first_output_socket_only.
    bool OpenOutputChannel(eprosima::fastdds::rtps::SendResourceList& sender_resource_list,
                           const eprosima::fastrtps::rtps::Locator_t& locator) override;

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
