// Decodes a serialized sample of a type the program was never compiled with, from its IDL (TypeLibrary). Payloads
// come from the network: any bytes give a value or an error, never a read past the end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "types/decoded_value.hpp"
#include "types/type_library.hpp"

namespace tgw::types {

/// A decoded sample, or why it could not be decoded.
struct CdrDecodeResult {
    std::optional<DecodedValue> value;  ///< a record of the struct's members, when it decoded
    std::string error;                  ///< why not: "topics[2].name: needs 40 bytes at offset 96, 12 are left"
};

/// Decodes `size` bytes of a sample as DDS carries it (the 4-byte encapsulation header first) as the struct
/// `type_name` of `types`. Encodings: XCDR1 plain (CDR_BE, CDR_LE: primitives aligned to their size, 8 for
/// 64-bit), XCDR2 (CDR2_BE/LE, D_CDR2_BE/LE: alignment at most 4; a DHEADER before an appendable struct and
/// before a sequence or array of non-primitive elements). A struct without @final/@appendable is taken as final
/// in CDR2 and as appendable in D_CDR2, as the encapsulation says. Mutable structs, parameter-list encodings and
/// @optional members give an error saying they cannot be decoded. Trailing bytes are ignored (padding).
/// `member_limit`: only the struct's first members are decoded (its base's counted first), the rest left unread;
/// what a key needs (KeyHasher), when the key members come first.
CdrDecodeResult decode_cdr(const std::uint8_t* data, std::size_t size, const std::string& type_name,
                           const TypeLibrary& types,
                           std::size_t member_limit = std::numeric_limits<std::size_t>::max());

}  // namespace tgw::types
