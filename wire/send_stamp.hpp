// When a Fast DDS participant sent a datagram, as its transport wrote it into the statistics submessage the
// datagram ends with: a clock reading taken at the send, and a count of the datagrams sent to that destination.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "base/time.hpp"

namespace tgw::wire {

struct SendStamp {
    std::array<std::uint8_t, 12> sender{};  ///< the GUID prefix in the RTPS header: the sending participant
    base::WallTime sent{};                  ///< the sender's wall clock as its transport sent the datagram
    /// The locator it was sent to, as the sender wrote it (kind, port, address): the sequence runs per destination.
    std::array<std::uint8_t, 24> destination{};
    std::uint64_t sequence = 0;  ///< the datagrams the sender has sent to `destination`, this one included
};

/// The stamp of a well-formed RTPS message that ends with Fast DDS's statistics submessage (Debian's build adds
/// one to every message and its UDP transport fills it in as it sends: little-endian, whatever the submessage's
/// flags say); nullopt for any other datagram: another vendor's, one whose sender left it out (a compact-mode
/// gateway strips it), or bytes that are not RTPS.
std::optional<SendStamp> read_send_stamp(const std::uint8_t* datagram, std::size_t size);

}  // namespace tgw::wire
