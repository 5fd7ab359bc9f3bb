// tm-basecamp merge: the full mission archive from the gateway's on-robot log and the base camp's recording.
#pragma once

#include <CLI/CLI.hpp>

#include "basecamp/cli/subcommand.hpp"

namespace tgw::basecamp {

/// Adds `merge ROBOT.db BASECAMP.db --out MISSION.db` to `app` and returns how to run it: writes the archive
/// (merge_mission) and prints one line per topic (produced, received, on time, dropped by reason, lost) and the
/// totals. Exit 0; 2 for an input that is missing or not what it should be (the message names it); 130 when
/// SIGINT or SIGTERM stopped it, MISSION.db as it was.
Subcommand add_merge_command(CLI::App& app);

}  // namespace tgw::basecamp
