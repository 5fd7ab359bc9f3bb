// A decoded sample as JSON, for `tm-basecamp echo --json`: one line per sample, so that jq and tests read it.
#pragma once

#include <ostream>
#include <string>

#include "types/decoded_value.hpp"

namespace tgw::basecamp {

/// `value` as JSON on one line: records as objects in member order, lists as arrays, enumerators by name (a
/// number when the enum declares no such value), characters as one-character strings, integers (64-bit too)
/// as numbers, reals with the shortest digits that read back the same; NaN and the infinities, which JSON
/// lacks, as the strings "nan", "inf" and "-inf".
void write_json(std::ostream& out, const types::DecodedValue& value);

/// A scalar of `value` (not a list or record) as a JSON token.
std::string json_scalar(const types::DecodedValue& value);

/// `text` as a JSON string literal, quotes included. Bytes that are not UTF-8 (a CDR string may hold any) are
/// written as \u00XX, so that the line stays valid JSON.
std::string json_string(const std::string& text);

}  // namespace tgw::basecamp
