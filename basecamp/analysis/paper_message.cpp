#include "basecamp/analysis/paper_message.hpp"

#include "base/byte_order.hpp"

namespace tgw::basecamp {

std::optional<std::uint32_t> paper_message_sequence(const std::uint8_t* payload, std::size_t size) {
    // Encapsulation (2 bytes representation id, 2 options), then generated_ns (8), then sequence (4).
    if (payload == nullptr || size < 16 || payload[0] != 0x00 || payload[1] > 0x01)
        return std::nullopt;
    return base::load_unsigned<std::uint32_t>(payload + 12, payload[1] == 0x01);
}

}  // namespace tgw::basecamp
