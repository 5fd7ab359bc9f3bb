#pragma once

#include <string>

#include "base/time.hpp"

namespace tgw::base {

/// `time` as ISO 8601 in UTC with `fraction_digits` (0 to 9) digits of the second, truncated:
/// "2026-11-24T20:01:22.000000123Z".
std::string utc_text(WallTime time, int fraction_digits = 9);

}  // namespace tgw::base
