#pragma once

#include <istream>
#include <string>

#include "base/rate_steps.hpp"

namespace tgw::sensor {

/// A link rate over time read from a trace file: steps, each holding from its time until the next step's.
using RateTrace = base::RateSteps;

/// Parses lines of `seconds bits_per_second` (both non-negative numbers; the rate may carry a k, M or G suffix).
/// `#` starts a comment to the end of the line; blank lines and CRLF line ends are allowed. Times must be strictly
/// increasing. Throws base::ConfigError "FILE:LINE: what is wrong" naming `file_name`, or "FILE: ..." if the trace
/// has no step at all.
RateTrace parse_rate_trace(std::istream& in, const std::string& file_name);

/// Opens `path` and parses it; throws base::ConfigError naming the file if it cannot be read or is malformed.
RateTrace load_rate_trace(const std::string& path);

}  // namespace tgw::sensor
