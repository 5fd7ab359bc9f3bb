// The base camp's measure of a fleet's shared channel (tm-basecamp relay --measure-channel): what arrives, what
// is lost on the way and how long it took, fed to core::ChannelEstimate.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <set>

#include "base/clock.hpp"
#include "basecamp/capture/delivery_tally.hpp"
#include "core/channel_estimate.hpp"

namespace tgw::basecamp {

/// Where a datagram came from: its sender's IP address (Fast DDS's Locator_t::address, IPv4 in the last four).
using SourceAddress = std::array<std::uint8_t, 16>;

/// What the meter found at its last measure.
struct ChannelReading {
    double channel_bps = 0;  ///< the rate it shares
    core::ChannelVerdict verdict = core::ChannelVerdict::unknown;
    std::optional<double> delivered_bps;     ///< core::ChannelEstimate::delivered_bps
    std::optional<base::Duration> queueing;  ///< core::ChannelEstimate::queueing
    std::uint64_t datagrams = 0;             ///< received so far
    std::uint64_t stamped_datagrams = 0;     ///< of them, with a sender's send stamp
    std::uint64_t lost_datagrams = 0;        ///< gaps in the senders' sequences
};

/// Thread-safe: the WAN transport's receive threads, the readers' listeners and the relay's thread meet here.
class ChannelMeter {
  public:
    /// A channel of `upper_bps` at most. Throws base::ConfigError when it is not a rate above 0.
    ChannelMeter(double upper_bps, const base::Clock& clock);

    /// One datagram off the WAN (MeteredTransport), `from` the address it came from. A gateway's (its RTPS header
    /// names a participant known by gateway() or stamped_sample()) crossed the channel, and so did any other from an
    /// address a gateway sent from (a robot's host: a gateway restarted there before its first status, its discovery
    /// a burst on the channel): its bytes count as delivered, and where its sender's transport stamped it
    /// (wire::read_send_stamp: a standard-mode gateway's every datagram) its delay and its place in the sender's
    /// sequence count too. Any other's did not cross it, and counts for nothing: Debian's fast-discovery-server
    /// beside the relay stamps its datagrams too, took no time, and hid a standing queue of 800 ms while the
    /// estimate grew to 87,565 bit/s on a channel of 60,000. A gateway on the camp's own host makes the camp's
    /// other participants count too.
    void datagram(const std::uint8_t* bytes, std::size_t size, const SourceAddress& from);

    /// `wire_bytes` the base camp itself sent on the channel (commands, where one channel carries both directions):
    /// the channel carried them, so they count as delivered. Uncounted, the commands the grants make room for left
    /// the estimate looking idle, and it never grew from its slow start (rover1 beside 19,360 bit/s of commands:
    /// 1 of 200 A on time).
    void camp_sent(std::uint64_t wire_bytes);

    /// A participant joined the WAN domain (core::ChannelEstimate::participant_joined).
    void participant_joined();

    /// `sender` is a robot's gateway (it sent a status): its datagrams cross the channel.
    void gateway(const ParticipantPrefix& sender);

    /// A sample from the gateway `sender` whose source timestamp is its write time (a compact bundle; a gateway's
    /// status), received `one_way` after it: for senders whose datagrams carry no stamp.
    void stamped_sample(const ParticipantPrefix& sender, base::Duration one_way, std::size_t wire_bytes);

    /// Once a grant period: `lost_samples` what the readers counted lost so far (DeliveryTally), and the grants
    /// added up to `granted_bps`. Returns what it found, the channel's rate to share among it
    /// (core::ChannelEstimate::update).
    ChannelReading measure(std::uint64_t lost_samples, double granted_bps);

    ChannelReading reading() const;

  private:
    ChannelReading reading_locked() const;

    using SequenceKey = std::array<std::uint8_t, 36>;  // the sender's prefix, then the destination it sent to

    const base::Clock& clock_;
    mutable std::mutex mutex_;
    core::ChannelEstimate estimate_;
    std::uint64_t delivered_wire_bytes_ = 0;
    std::uint64_t datagrams_ = 0;
    std::uint64_t stamped_datagrams_ = 0;
    std::uint64_t lost_datagrams_ = 0;
    std::map<SequenceKey, std::uint64_t> last_sequence_;
    std::set<ParticipantPrefix> gateways_;
    std::set<SourceAddress> gateway_addresses_;  ///< where the gateways' datagrams came from
};

}  // namespace tgw::basecamp
