#pragma once

#include <istream>
#include <string>
#include <vector>

#include "core/paper_workload.hpp"

namespace tgw::robot_sim {

/// Parses a workload: one stream per line, `TYPE TOPIC DATA_BYTES TTL_S [RATE_HZ]`; `#` starts a comment.
/// Streams without a rate get `default_rate_hz`. Throws base::ConfigError naming `name` and the line.
std::vector<core::MessageStream> parse_workload(std::istream& in, const std::string& name, double default_rate_hz);

/// "paper" gives the paper's four streams at `rate_hz`; anything else is read as a workload file.
std::vector<core::MessageStream> load_workload(const std::string& spec, double rate_hz);

}  // namespace tgw::robot_sim
