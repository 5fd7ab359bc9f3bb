#pragma once

#include <cstddef>
#include <cstdint>

namespace tgw::base {

/// An unsigned integer of `sizeof(U)` bytes read from `bytes` in the byte order given (CDR payloads carry theirs
/// in the encapsulation; RTPS submessages in a flag). No alignment needed.
template <typename U>
U load_unsigned(const std::uint8_t* bytes, bool little_endian) {
    U value = 0;
    for (std::size_t i = 0; i < sizeof(U); ++i)
        value |= static_cast<U>(static_cast<U>(bytes[little_endian ? i : sizeof(U) - 1 - i]) << (8 * i));
    return value;
}

/// The same, little endian: the compact codec's fields, Fast DDS's statistics submessage.
template <typename U>
U load_little_endian(const std::uint8_t* bytes) {
    return load_unsigned<U>(bytes, true);
}

}  // namespace tgw::base
