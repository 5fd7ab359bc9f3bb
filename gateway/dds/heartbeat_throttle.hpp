// Keeps a reliable writer from answering a storm of ACKNACKs with a storm of HEARTBEATs on a slow link.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <unordered_map>

#include "base/time.hpp"
#include "gateway/dds/datagram_coalescer.hpp"

namespace tgw::dds {

/// A Fast DDS 2.9 reader that has matched a writer sends it an ACKNACK every 70 ms until a HEARTBEAT from it
/// arrives, and the writer answers each with a HEARTBEAT of its own. On a slow link the first HEARTBEAT waits in
/// the shaper's queue while a dozen more follow it: measured at 10,000 bit/s (scripts/demo --reliable-wan
/// --capture), one writer sent 14 identical HEARTBEATs in a row, 170 bytes each, and the shaper dropped 86
/// packets at start-up.
///
/// This passes every message except a HEARTBEAT (alone, with only INFO_DST and Fast DDS's statistics around it)
/// that repeats one sent to the same destination less than `interval` ago: same reader, writer and sequence
/// range. The one sent first still brings the reader what the repeat would have; a HEARTBEAT that says anything
/// new (a sequence range that moved), a piggy-backed one, and every other submessage pass.
class HeartbeatThrottle {
  public:
    /// What the scheduler lets the link queue hold (SchedulerConfig::link_queue): a HEARTBEAT sent that long
    /// ago has had time to arrive.
    static constexpr base::Duration DEFAULT_INTERVAL = std::chrono::seconds(1);

    explicit HeartbeatThrottle(base::Duration interval = DEFAULT_INTERVAL) : interval_(interval) {}

    /// True if `message`, an RTPS message to `destination`, may be sent at `now`.
    bool admit(const DatagramDestination& destination, const std::uint8_t* message, std::size_t size,
               base::SteadyTime now);

    /// Repeated HEARTBEATs held back so far.
    std::uint64_t suppressed() const;

  private:
    struct Key {
        std::uint64_t destination = 0;        ///< a hash of the channel and the locators
        std::uint8_t reader_prefix[12] = {};  ///< INFO_DST's GUID prefix; zeros without one
        std::uint8_t heartbeat[24] = {};      ///< reader id, writer id, first and last sequence numbers
        bool operator==(const Key& other) const;
    };
    struct KeyHash {
        std::size_t operator()(const Key& key) const;
    };

    /// The key (but its destination) of a message that carries a lone HEARTBEAT; false for any other message.
    static bool lone_heartbeat(const std::uint8_t* message, std::size_t size, Key& key);

    const base::Duration interval_;
    mutable std::mutex mutex_;
    std::unordered_map<Key, base::SteadyTime, KeyHash> last_sent_;
    std::uint64_t suppressed_ = 0;
};

}  // namespace tgw::dds
