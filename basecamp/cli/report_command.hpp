// tm-basecamp report: the paper's metrics per topic from a recording, and with the gateway's on-robot log where
// every missing sample went.
#pragma once

#include "basecamp/cli/subcommand.hpp"

namespace tgw::basecamp {

/// Adds `report FILE [--ttl TOPIC=S] [--qos FILE] [--offered TOPIC=N] [--robot-log FILE] ...` to `app` and returns
/// how to run it: prints the per-topic table (read_report), the fleet's grants when the recording has them and,
/// with --link-rate, the on-time payload. Exit 0; 2 for a FILE that is not a recording or a bad flag (the message
/// names it).
Subcommand add_report_command(CLI::App& app);

}  // namespace tgw::basecamp
