// What a sample sent by itself puts on the WAN, in either WAN mode: what a robot's least share must pay for.
#pragma once

#include <cstddef>

#include "core/wire_model.hpp"

namespace tgw::core {

/// A sample sent by itself: a DDS sample of its own in standard WAN mode, a bundle of its own in compact mode
/// (`bundles`). The non-preemptive rule sends a status too long to share a bundle with the most urgent topic's
/// sample so, and that sample after it in another: a bundle's header, checksum and DDS envelope each time, on top
/// of the datagram's. Sized without knowing the topic's id or lane: at their largest encodings.
struct AloneWire {
    WireModel wire;
    bool bundles = false;

    /// Bytes on the wire for one sample of `payload_bytes` serialized bytes (`keyed`: with its instance key).
    std::size_t wire_bytes(std::size_t payload_bytes, bool keyed = false) const;
};

}  // namespace tgw::core
