#pragma once

#include <cstddef>
#include <cstdint>

namespace tgw::core {

/// What a sample costs on the link beyond its serialized payload. Defaults are what Fast DDS 2.9 puts on a
/// tbf-shaped veth for a best-effort writer sending one sample per datagram (DESIGN section 2): Ethernet 14,
/// IPv4 20, UDP 8, RTPS header 20 per datagram; INFO_TS 12 and DATA 24 per sample; payload padded to 4.
/// Large samples fragment (DATA_FRAG): each fragment pays the datagram and a DATA_FRAG header again.
struct WireModel {
    std::size_t per_datagram_bytes = 62;
    std::size_t per_sample_bytes = 36;
    std::size_t per_fragment_bytes = 36;        ///< DATA_FRAG submessage header
    std::size_t fragment_payload_bytes = 1344;  ///< payload carried by one fragment before a new datagram
    std::size_t max_unfragmented_bytes = 1400;  ///< payloads larger than this go as DATA_FRAG

    /// Bytes on the wire for one sample of `payload_bytes` serialized bytes sent alone.
    std::size_t wire_bytes(std::size_t payload_bytes) const;
    std::uint64_t wire_bits(std::size_t payload_bytes) const { return 8u * wire_bytes(payload_bytes); }
};

}  // namespace tgw::core
