// A sample decoded field by field (decode_cdr), for printing as text or JSON.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace tgw::types {

/// A value of any IDL type: a scalar, a list (sequence, array) or a record (struct).
struct DecodedValue {
    enum class Kind { boolean, signed_integer, unsigned_integer, real, character, string, enumerator, list, record };

    Kind kind = Kind::record;
    bool boolean = false;
    std::int64_t signed_integer = 0;  ///< signed integers, and an enumerator's value
    std::uint64_t unsigned_integer = 0;
    double real = 0.0;
    bool single_precision = false;    ///< `real` came from a float: printed with a float's shortest digits
    std::string text;                 ///< string, character; an enumerator's name (empty: a value not declared)
    std::vector<DecodedValue> items;  ///< list: sequence and array elements
    std::vector<std::pair<std::string, DecodedValue>> fields;  ///< record: struct members in declaration order

    bool is_scalar() const { return kind != Kind::list && kind != Kind::record; }
};

}  // namespace tgw::types
