#include "gateway/dds/coalescing_transport.hpp"

#include <algorithm>
#include <iterator>
#include <optional>
#include <vector>

#include <fastdds/rtps/network/SenderResource.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastdds/rtps/common/LocatorsIterator.hpp>

#include "core/wire_model.hpp"
#include "gateway/dds/early_heartbeats.hpp"
#include "gateway/dds/unstamped_write.hpp"

namespace tgw::dds {

namespace rtps = eprosima::fastrtps::rtps;

namespace {

// What a send of a datagram that waited may block for when the socket buffer is full: Fast DDS's default
// max_blocking_time of a write.
constexpr std::chrono::milliseconds SEND_TIMEOUT{100};

/// Walks a DatagramDestination's locators for SenderResource::send.
class LocatorVectorIterator final : public eprosima::fastdds::rtps::LocatorsIterator {
  public:
    explicit LocatorVectorIterator(std::vector<rtps::Locator_t>::const_iterator it) : it_(it) {}

    LocatorsIterator& operator++() override {
        ++it_;
        return *this;
    }
    bool operator==(const LocatorsIterator& other) const override {
        return it_ == static_cast<const LocatorVectorIterator&>(other).it_;
    }
    bool operator!=(const LocatorsIterator& other) const override { return !(*this == other); }
    const rtps::Locator_t& operator*() const override { return *it_; }

  private:
    std::vector<rtps::Locator_t>::const_iterator it_;
};

}  // namespace

CoalescingTransportDescriptor::CoalescingTransportDescriptor(
    std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface> low_level,
    std::shared_ptr<DatagramCoalescer> coalescer_in, UnscheduledTrafficCallback on_unscheduled_in,
    std::shared_ptr<RepeatThrottle> repeat_throttle_in)
    : ChainingTransportDescriptor(std::move(low_level)),
      coalescer(std::move(coalescer_in)),
      on_unscheduled(std::move(on_unscheduled_in)),
      repeat_throttle(std::move(repeat_throttle_in)) {}

eprosima::fastdds::rtps::TransportInterface* CoalescingTransportDescriptor::create_transport() const {
    return new CoalescingTransport(*this);
}

CoalescingTransport::CoalescingTransport(const CoalescingTransportDescriptor& descriptor)
    : ChainingTransport(descriptor), descriptor_(descriptor), coalescer_(descriptor.coalescer) {}

CoalescingTransport::~CoalescingTransport() {
    if (coalescer_)
        coalescer_->forget(*this);
    if (descriptor_.repair_desk)
        descriptor_.repair_desk->forget(*this);
}

bool CoalescingTransport::OpenOutputChannel(eprosima::fastdds::rtps::SendResourceList& sender_resource_list,
                                            const rtps::Locator_t& locator) {
    const std::size_t before = sender_resource_list.size();
    const bool opened = ChainingTransport::OpenOutputChannel(sender_resource_list, locator);
    if (opened && descriptor_.first_output_socket_only && sender_resource_list.size() > before + 1) {
        // The multicast sockets close with their resources.
        sender_resource_list.erase(sender_resource_list.begin() + static_cast<std::ptrdiff_t>(before + 1),
                                   sender_resource_list.end());
    }
    return opened;
}

bool CoalescingTransport::send(rtps::SenderResource* low_sender_resource, const rtps::octet* send_buffer,
                               std::uint32_t send_buffer_size, rtps::LocatorsIterator* destination_locators_begin,
                               rtps::LocatorsIterator* destination_locators_end,
                               const std::chrono::steady_clock::time_point& timeout) {
    // Every datagram, sent now or after waiting, gets SEND_TIMEOUT: the coalescer keeps no per-message timeout.
    (void)timeout;
    // Reused per thread: a send must not allocate.
    thread_local DatagramDestination destination;
    destination.channel = low_sender_resource;
    destination.locators.clear();
    for (rtps::LocatorsIterator& it = *destination_locators_begin; it != *destination_locators_end; ++it) {
        destination.locators.push_back(*it);
    }
    const bool scheduled_write = DatagramCoalescer::DeferScope::current() != 0;
    const bool strip_timestamp = descriptor_.strip_timestamp && UnstampedWrite::active();
    // A scheduled write's message carries its sample: only the rest need reading for it.
    const bool strip_unless_sample = descriptor_.strip_statistics_without_samples && !scheduled_write;
    if (descriptor_.strip_destination || descriptor_.strip_statistics || strip_unless_sample || strip_timestamp) {
        const wire::RtpsDatagram::Strippable strip = wire::RtpsDatagram::strippable(send_buffer, send_buffer_size);
        if (descriptor_.strip_statistics || (strip_unless_sample && !strip.carries_user_sample)) {
            // The trailer is the message's last submessage: the message without it is its first bytes.
            send_buffer_size -= static_cast<std::uint32_t>(strip.trailer_bytes);
        }
        // Both come right after the header, the INFO_DST first: one cut leaves out either or both.
        std::size_t cut = 0;
        if (descriptor_.strip_destination && strip.destination_bytes > 0 &&
            std::none_of(destination.locators.begin(), destination.locators.end(),
                         [](const rtps::Locator_t& locator) { return rtps::IPLocator::isMulticast(locator); })) {
            // Only that participant listens at its unicast locators: without the INFO_DST the message reads the
            // same.
            cut += strip.destination_bytes;
        }
        if (strip_timestamp && strip.timestamp_bytes > 0 && (cut > 0 || strip.destination_bytes == 0)) {
            // The sample's payload holds its write time; the receiver takes it as a sample without a timestamp.
            cut += strip.timestamp_bytes;
        }
        if (cut > 0) {
            const rtps::octet* rest = send_buffer + wire::RtpsDatagram::HEADER_BYTES + cut;
            thread_local std::vector<rtps::octet> stripped;
            stripped.assign(send_buffer, send_buffer + wire::RtpsDatagram::HEADER_BYTES);
            stripped.insert(stripped.end(), rest, send_buffer + send_buffer_size);
            send_buffer = stripped.data();
            send_buffer_size -= static_cast<std::uint32_t>(cut);
        }
    }
    if (descriptor_.strip_early_heartbeats) {
        thread_local std::vector<rtps::octet> without_heartbeats;
        if (without_early_heartbeats(send_buffer, send_buffer_size, without_heartbeats)) {
            send_buffer = without_heartbeats.data();
            send_buffer_size = static_cast<std::uint32_t>(without_heartbeats.size());
        }
    }
    // Only locators this transport sends to count (a remote reader may also announce shared memory ones).
    const auto copies = static_cast<std::size_t>(
        std::count_if(destination.locators.begin(), destination.locators.end(),
                      [this](const rtps::Locator_t& locator) { return IsLocatorSupported(locator); }));
    // Read once, when a scheduled write's message needs it.
    std::optional<std::size_t> heartbeat;
    const auto heartbeat_bytes = [&] {
        if (!heartbeat) {
            heartbeat = wire::RtpsDatagram::heartbeat_bytes(send_buffer, send_buffer_size);
        }
        return *heartbeat;
    };
    if (descriptor_.repair_desk) {
        if (scheduled_write) {
            // The write was charged for one copy of the sample, without the HEARTBEAT a reliable writer adds.
            const std::size_t prepaid = send_buffer_size + core::WireModel::FRAME_HEADER_BYTES - heartbeat_bytes();
            if (descriptor_.repair_desk->note_scheduled(*this, destination, send_buffer, send_buffer_size, copies,
                                                        prepaid)) {
                return true;  // a fragment after its sample's first: the schedule sends it
            }
        } else {
            thread_local std::vector<rtps::octet> gap;
            switch (descriptor_.repair_desk->hold(*this, destination, send_buffer, send_buffer_size, copies, gap)) {
                case RepairDesk::Verdict::held:
                    return true;  // the schedule sends it, or finds it too late
                case RepairDesk::Verdict::gap:
                    send_buffer = gap.data();  // the samples are past their deadlines: the reader stops asking
                    send_buffer_size = static_cast<std::uint32_t>(gap.size());
                    break;
                case RepairDesk::Verdict::send:
                    break;
            }
        }
    }
    if (!scheduled_write && descriptor_.repeat_throttle &&
        !descriptor_.repeat_throttle->admit(destination, send_buffer, send_buffer_size, base::SteadyClock::now())) {
        return true;  // the same HEARTBEAT or ACKNACK went there a moment ago
    }
    if (!scheduled_write && descriptor_.repair_desk &&
        descriptor_.repair_desk->hold_announcement(
            *this, destination, send_buffer, send_buffer_size,
            [this](const rtps::Locator_t& locator) { return IsLocatorSupported(locator); })) {
        return true;  // the schedule sends its copies, and charges them as they leave
    }
    if (!scheduled_write && descriptor_.repair_desk &&
        descriptor_.repair_desk->hold_writer_announcement(*this, destination, send_buffer, send_buffer_size, copies)) {
        return true;  // the schedule sends it in its topic's urgency, and charges it as it leaves
    }
    if (!scheduled_write && coalescer_->holds_control() && copies > 0 &&
        wire::RtpsDatagram::user_control_only(send_buffer, send_buffer_size)) {
        return coalescer_->hold(*this, destination, send_buffer, send_buffer_size, copies);  // charged as it leaves
    }
    // A scheduled write was charged for one copy of its message, without the HEARTBEAT a reliable writer may
    // have put in it; everything else is reported.
    if (descriptor_.on_unscheduled) {
        const std::size_t scheduled = scheduled_write ? 1 : 0;
        std::uint64_t unscheduled = 0;
        if (copies > scheduled) {
            unscheduled += (copies - scheduled) * (send_buffer_size + core::WireModel::FRAME_HEADER_BYTES);
        }
        if (copies > 0 && scheduled > 0) {
            unscheduled += heartbeat_bytes();
        }
        if (unscheduled > 0) {
            descriptor_.on_unscheduled(unscheduled);
        }
    }
    return coalescer_->send(*this, destination, send_buffer, send_buffer_size);
}

void CoalescingTransport::receive(eprosima::fastdds::rtps::TransportReceiverInterface* next_receiver,
                                  const rtps::octet* receive_buffer, std::uint32_t receive_buffer_size,
                                  const rtps::Locator_t& local_locator, const rtps::Locator_t& remote_locator) {
    next_receiver->OnDataReceived(receive_buffer, receive_buffer_size, local_locator, remote_locator);
}

bool CoalescingTransport::send_datagram(const DatagramDestination& destination, const std::uint8_t* bytes,
                                        std::size_t size) {
    if (descriptor_.strip_statistics || descriptor_.strip_statistics_without_samples) {
        // Without its statistics submessage a datagram may still look as if it ended with one to the UDP
        // transport below, which would then write over its last 60 bytes: a payload's, or a protected message's
        // signature (seen once in about 10 secured compact-mode runs). PADs at the end keep it whole.
        const std::size_t padding = wire::RtpsDatagram::padding_against_statistics_fill(bytes, size);
        if (padding > 0) {
            thread_local std::vector<std::uint8_t> padded;
            padded.assign(bytes, bytes + size);
            for (std::size_t i = 0; i < padding; i += sizeof(wire::RtpsDatagram::PAD_SUBMESSAGE)) {
                padded.insert(padded.end(), std::begin(wire::RtpsDatagram::PAD_SUBMESSAGE),
                              std::end(wire::RtpsDatagram::PAD_SUBMESSAGE));
            }
            bytes = padded.data();
            size = padded.size();
        }
    }
    auto* channel = static_cast<rtps::SenderResource*>(const_cast<void*>(destination.channel));
    LocatorVectorIterator begin(destination.locators.begin());
    LocatorVectorIterator end(destination.locators.end());
    return channel->send(bytes, static_cast<std::uint32_t>(size), &begin, &end,
                         std::chrono::steady_clock::now() + SEND_TIMEOUT);
}

}  // namespace tgw::dds
