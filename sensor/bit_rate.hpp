#pragma once

#include <optional>
#include <string_view>

namespace tgw::sensor {

/// Parses a bit rate as operators write it: a plain number of bit/s ("20000", "1.5e4") or one with a decimal
/// suffix, k = 1e3, M = 1e6, G = 1e9 ("20k", "1.5M"). Returns nullopt unless the whole text is such a finite
/// number; the sign is the caller's to judge.
std::optional<double> parse_bit_rate(std::string_view text);

}  // namespace tgw::sensor
