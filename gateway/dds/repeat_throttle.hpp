// Keeps the WAN participant from repeating the same HEARTBEAT, ACKNACK, handshake or announcement on a slow link.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <unordered_map>

#include "base/time.hpp"
#include "gateway/dds/datagram_coalescer.hpp"

namespace tgw::dds {

/// A Fast DDS 2.9 reader that has matched a writer sends it an ACKNACK every 70 ms until a HEARTBEAT from it
/// arrives, and the writer answers each with a HEARTBEAT of its own.
/// - On a slow link the first HEARTBEAT waits in the shaper's queue while a dozen more follow it: measured at
///   10,000 bit/s (scripts/demo --reliable-wan --capture), one writer sent 14 identical HEARTBEATs in a row,
///   170 bytes each, and the shaper dropped 86 packets at start-up.
/// - A base camp that restarts is discovered by the gateway before it has heard of the gateway, and ignores
///   what it gets from it until then: the gateway's readers then sent an ACKNACK every 70 ms to each of its
///   builtin writers, enough to fill a 20,000 bit/s link (174 kB in one run) and crowd out the announcement
///   that would have introduced them.
///
/// - With DDS Security, Fast DDS 2.9 resends an authentication handshake message every 500 ms until it is
///   answered (hard-coded): 5.5 kB each with scripts/make-certs' files, 88,000 bit/s, where one takes 1.1 s to
///   cross a 40,000 bit/s link.
///
/// - Fast DDS 2.9 sends each periodic announcement of the participant (SPDP) once to an initial peer and once
///   more to the participant it discovered there, at the same address and port: two 446-byte frames every 20 s
///   to a base camp named with --wan-peer, 0.7 % of a 25,000 bit/s link (captured on the testbed).
///
/// This passes every message except a lone HEARTBEAT or ACKNACK (alone, with only INFO_DST and Fast DDS's
/// statistics around it) that repeats one sent to the same destination less than `interval` ago: same reader,
/// writer and sequence numbers, only its count moved; and a handshake message (the DATA of the participant
/// stateless message writer) that repeats one sent there less than `handshake_interval` ago: the same payload
/// under a new sequence number; and an announcement that repeats one sent there less than `announcement_interval`
/// ago. The one sent first brings the other side what the repeat would have; one that says anything new, a
/// piggy-backed one, and every other submessage pass.
class RepeatThrottle {
  public:
    /// What the scheduler lets the link queue hold (SchedulerConfig::link_queue): a message sent that long ago
    /// has had time to arrive.
    static constexpr base::Duration DEFAULT_INTERVAL = std::chrono::seconds(1);
    /// Long enough for a 5.5 kB handshake message to cross a 10,000 bit/s link before the next.
    static constexpr base::Duration DEFAULT_HANDSHAKE_INTERVAL = std::chrono::seconds(5);
    /// Shorter than the 100 ms between the announcements Fast DDS repeats on purpose at start-up, longer than the
    /// moment between a copy to an initial peer and one to the same participant discovered.
    static constexpr base::Duration DEFAULT_ANNOUNCEMENT_INTERVAL = std::chrono::milliseconds(50);

    explicit RepeatThrottle(base::Duration interval = DEFAULT_INTERVAL,
                            base::Duration handshake_interval = DEFAULT_HANDSHAKE_INTERVAL,
                            base::Duration announcement_interval = DEFAULT_ANNOUNCEMENT_INTERVAL)
        : interval_(interval), handshake_interval_(handshake_interval), announcement_interval_(announcement_interval) {}

    /// True if `message`, an RTPS message to `destination`, may be sent at `now`.
    bool admit(const DatagramDestination& destination, const std::uint8_t* message, std::size_t size,
               base::SteadyTime now);

    /// Repeats held back so far: HEARTBEATs, ACKNACKs, handshake messages, announcements.
    std::uint64_t suppressed() const;

  private:
    /// An ACKNACK's body but its count: reader and writer ids, the set's base and bit count, and a bitmap of at
    /// most 256 bits (DDSI-RTPS 9.4.2.6).
    static constexpr std::size_t MAX_REPEAT_BYTES = 4 + 4 + 8 + 4 + 32;

    struct Key {
        std::uint64_t destination = 0;        ///< a hash of the channel and the locators
        std::uint8_t reader_prefix[12] = {};  ///< INFO_DST's GUID prefix; zeros without one
        std::uint8_t kind = 0;                ///< HEARTBEAT or ACKNACK
        std::uint8_t length = 0;              ///< bytes of `body` in use
        /// The submessage's body without its trailing count; for a handshake message its reader and writer ids
        /// and a hash of what follows its sequence number.
        std::uint8_t body[MAX_REPEAT_BYTES] = {};
        bool operator==(const Key& other) const;
    };
    struct KeyHash {
        std::size_t operator()(const Key& key) const;
    };

    /// The key (but its destination) of a message that carries a lone HEARTBEAT, ACKNACK, handshake message or
    /// announcement; false for any other message.
    static bool lone_repeatable(const std::uint8_t* message, std::size_t size, Key& key);

    const base::Duration interval_;
    const base::Duration handshake_interval_;
    const base::Duration announcement_interval_;
    mutable std::mutex mutex_;
    std::unordered_map<Key, base::SteadyTime, KeyHash> last_sent_;
    std::uint64_t suppressed_ = 0;
};

}  // namespace tgw::dds
