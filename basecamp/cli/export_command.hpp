// tm-basecamp export: a recording (record, relay --out) as an MCAP file for Foxglove, rosbag2 and the MCAP tools.
#pragma once

#include "basecamp/cli/subcommand.hpp"

namespace tgw::basecamp {

/// Adds `export FILE.db --mcap FILE.mcap [--compression C] [--idl DIR]` to `app` and returns how to run it: one
/// channel per topic, the samples in order of receive time, a schema per type (McapRecording). Exit 0; 1 when
/// writing the MCAP file failed; 2 for a FILE that is not a recording or a bad flag (the message names it).
Subcommand add_export_command(CLI::App& app);

}  // namespace tgw::basecamp
