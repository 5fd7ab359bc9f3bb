#include "core/wire_model.hpp"

#include <algorithm>

namespace tgw::core {

namespace {
std::size_t padded_to_4(std::size_t n) {
    return (n + 3u) & ~std::size_t{3u};
}
// Ethernet and IPv4 headers of each frame, and the IP payload of a 1500-byte MTU.
constexpr std::size_t ETHERNET_IP_HEADER_BYTES = 14 + 20;
constexpr std::size_t IP_PAYLOAD_PER_FRAME = 1480;
// Headers between maxMessageSize and what Fast DDS puts in one DATA or DATA_FRAG (1472 - 1308, 1472 - 1296).
constexpr std::size_t UNFRAGMENTED_HEADROOM_BYTES = 164;
constexpr std::size_t FRAGMENT_HEADROOM_BYTES = 176;
}  // namespace

WireModel WireModel::for_max_datagram(std::size_t max_datagram_bytes) {
    WireModel model;
    model.max_datagram_bytes = max_datagram_bytes;
    // Below the headroom (refused by GatewayConfig::validate) every sample fragments into 1-byte pieces.
    model.max_unfragmented_bytes =
        std::max(max_datagram_bytes, UNFRAGMENTED_HEADROOM_BYTES + 1) - UNFRAGMENTED_HEADROOM_BYTES;
    model.fragment_payload_bytes = std::max(max_datagram_bytes, FRAGMENT_HEADROOM_BYTES + 1) - FRAGMENT_HEADROOM_BYTES;
    return model;
}

WireModel WireModel::with_security() const {
    WireModel model = *this;
    const std::size_t sample_headers = 2 * SECURE_SUBMESSAGE_BYTES;  // INFO_TS and DATA, or INFO_TS and DATA_FRAG
    model.per_datagram_bytes += SECURE_MESSAGE_BYTES;
    model.per_sample_bytes += sample_headers;
    model.per_fragment_bytes += sample_headers;
    model.payload_overhead_bytes += SECURE_PAYLOAD_BYTES;
    model.protected_fill_margin_bytes = SECURE_FILL_MARGIN_BYTES;
    const std::size_t headroom = SECURE_MESSAGE_BYTES + sample_headers + SECURE_PAYLOAD_BYTES;
    model.max_unfragmented_bytes = std::max(model.max_unfragmented_bytes, headroom + 1) - headroom;
    model.fragment_payload_bytes = std::max(model.fragment_payload_bytes, headroom + 1) - headroom;
    return model;
}

std::size_t WireModel::datagram_wire_bytes(std::size_t submessage_bytes) const {
    const std::size_t bytes = per_datagram_bytes + submessage_bytes;
    // per_datagram_bytes holds one frame's Ethernet, IP and UDP headers; a datagram past one frame's IP
    // payload leaves as IP fragments, each adding its own Ethernet and IP headers.
    const std::size_t ip_payload = bytes - ETHERNET_IP_HEADER_BYTES;
    const std::size_t frames = std::max<std::size_t>(1, (ip_payload + IP_PAYLOAD_PER_FRAME - 1) / IP_PAYLOAD_PER_FRAME);
    return bytes + (frames - 1) * ETHERNET_IP_HEADER_BYTES;
}

std::size_t WireModel::wire_bytes(std::size_t serialized_bytes) const {
    const std::size_t payload_bytes = serialized_bytes + payload_overhead_bytes;
    if (payload_bytes <= max_unfragmented_bytes || fragment_payload_bytes == 0) {
        return datagram_wire_bytes(per_sample_bytes + padded_to_4(payload_bytes));
    }
    const std::size_t fragments = (payload_bytes + fragment_payload_bytes - 1) / fragment_payload_bytes;
    const std::size_t last_fragment = payload_bytes - (fragments - 1) * fragment_payload_bytes;
    return (fragments - 1) * datagram_wire_bytes(per_fragment_bytes + fragment_payload_bytes) +
           datagram_wire_bytes(per_fragment_bytes + padded_to_4(last_fragment));
}

std::size_t WireModel::first_datagram_wire_bytes(std::size_t serialized_bytes) const {
    const std::size_t payload_bytes = serialized_bytes + payload_overhead_bytes;
    if (payload_bytes <= max_unfragmented_bytes || fragment_payload_bytes == 0) {
        return wire_bytes(serialized_bytes);
    }
    return datagram_wire_bytes(per_fragment_bytes + fragment_payload_bytes);
}

}  // namespace tgw::core
