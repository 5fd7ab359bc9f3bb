#include "core/alone_wire.hpp"

#include <cstdint>
#include <limits>

#include "core/bundle_builder.hpp"

namespace tgw::core {

std::size_t AloneWire::wire_bytes(std::size_t payload_bytes, bool keyed) const {
    if (!bundles) {
        return wire.wire_bytes(payload_bytes);
    }
    // Its topic id and lane at their longest encodings, its payload's encapsulation header kept (not plain CDR).
    const BundleBuilder::Entry entry{std::numeric_limits<TopicId>::max(),
                                     std::numeric_limits<std::uint16_t>::max(),
                                     base::WallTime{},
                                     payload_bytes,
                                     false,
                                     keyed};
    return static_cast<std::size_t>(BundleBuilder(wire).alone_wire_bits(entry) / 8);
}

}  // namespace tgw::core
