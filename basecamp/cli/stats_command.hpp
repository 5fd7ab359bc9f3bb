#pragma once

#include "basecamp/cli/subcommand.hpp"

namespace tgw::basecamp {

/// `tm-basecamp stats [--once]`: one line per topic of a domain with Hz, bit/s, mean and p99 transmission time,
/// % within TTL and samples logged on the robot, refreshed every second (TopicStats).
Subcommand add_stats_command(CLI::App& app);

}  // namespace tgw::basecamp
