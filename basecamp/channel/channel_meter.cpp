#include "basecamp/channel/channel_meter.hpp"

#include <algorithm>
#include <string>

#include "core/wire_model.hpp"
#include "wire/rtps_datagram.hpp"
#include "wire/send_stamp.hpp"

namespace tgw::basecamp {

namespace {

std::string key_of(const std::array<std::uint8_t, 12>& prefix) {
    return std::string(prefix.begin(), prefix.end());
}

}  // namespace

ChannelMeter::ChannelMeter(double upper_bps, const base::Clock& clock)
    : clock_(clock), estimate_(upper_bps, core::ChannelEstimateConfig{}, clock) {}

void ChannelMeter::datagram(const std::uint8_t* bytes, std::size_t size, const SourceAddress& from) {
    const std::optional<ParticipantPrefix> sender = wire::RtpsDatagram::sender(bytes, size);
    if (!sender)
        return;
    const std::optional<wire::SendStamp> stamp = wire::read_send_stamp(bytes, size);
    const base::WallTime now = clock_.wall_now();
    std::lock_guard<std::mutex> lock(mutex_);
    if (gateways_.count(*sender) != 0) {
        gateway_addresses_.insert(from);
    } else if (gateway_addresses_.count(from) == 0) {
        return;
    }
    delivered_wire_bytes_ += size + core::WireModel::FRAME_HEADER_BYTES;
    ++datagrams_;
    if (!stamp)
        return;
    ++stamped_datagrams_;
    estimate_.arrived(key_of(stamp->sender), now - stamp->sent, size + core::WireModel::FRAME_HEADER_BYTES);
    SequenceKey key;
    std::copy(stamp->sender.begin(), stamp->sender.end(), key.begin());
    std::copy(stamp->destination.begin(), stamp->destination.end(), key.begin() + stamp->sender.size());
    auto [last, first] = last_sequence_.try_emplace(key, stamp->sequence);
    if (first)
        return;
    // A gap is datagrams the channel dropped; one that comes late (behind a later one) is left as lost.
    if (stamp->sequence > last->second) {
        lost_datagrams_ += stamp->sequence - last->second - 1;
        last->second = stamp->sequence;
    }
}

void ChannelMeter::participant_joined() {
    std::lock_guard<std::mutex> lock(mutex_);
    estimate_.participant_joined();
}

void ChannelMeter::gateway(const ParticipantPrefix& sender) {
    std::lock_guard<std::mutex> lock(mutex_);
    gateways_.insert(sender);
}

void ChannelMeter::stamped_sample(const ParticipantPrefix& sender, base::Duration one_way, std::size_t wire_bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    gateways_.insert(sender);
    estimate_.arrived(key_of(sender), one_way, wire_bytes);
}

void ChannelMeter::camp_sent(std::uint64_t wire_bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    delivered_wire_bytes_ += wire_bytes;
}

ChannelReading ChannelMeter::measure(std::uint64_t lost_samples, double granted_bps) {
    std::lock_guard<std::mutex> lock(mutex_);
    estimate_.update(delivered_wire_bytes_, lost_datagrams_ + lost_samples, granted_bps);
    return reading_locked();
}

ChannelReading ChannelMeter::reading() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return reading_locked();
}

ChannelReading ChannelMeter::reading_locked() const {
    return ChannelReading{estimate_.channel_bps(), estimate_.verdict(), estimate_.delivered_bps(),
                          estimate_.queueing(),    datagrams_,          stamped_datagrams_,
                          lost_datagrams_};
}

}  // namespace tgw::basecamp
