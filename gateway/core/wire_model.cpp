#include "gateway/core/wire_model.hpp"

namespace tgw::core {

namespace {
std::size_t padded_to_4(std::size_t n) {
    return (n + 3u) & ~std::size_t{3u};
}
}  // namespace

std::size_t WireModel::wire_bytes(std::size_t payload_bytes) const {
    if (payload_bytes <= max_unfragmented_bytes || fragment_payload_bytes == 0) {
        return per_datagram_bytes + per_sample_bytes + padded_to_4(payload_bytes);
    }
    const std::size_t fragments = (payload_bytes + fragment_payload_bytes - 1) / fragment_payload_bytes;
    return fragments * (per_datagram_bytes + per_fragment_bytes) + padded_to_4(payload_bytes);
}

}  // namespace tgw::core
