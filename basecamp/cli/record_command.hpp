// tm-basecamp record: every topic of a domain into a recording (SQLite, MCAP, or both).
#pragma once

#include "basecamp/cli/subcommand.hpp"

namespace tgw::basecamp {

/// Adds `record [--out FILE.db] [--mcap FILE.mcap] [--domain N] ...` to `app` and returns how to run it: subscribes
/// to every topic of the domain (Recorder) until --duration or SIGINT/SIGTERM, then prints what each topic and
/// each sending participant delivered. Exit 0; 1 when writing the MCAP file failed; 2 for a bad flag (the message
/// names it).
Subcommand add_record_command(CLI::App& app);

}  // namespace tgw::basecamp
