// tm-basecamp linkmap: the link-quality map of a mission, as a PNG.
#pragma once

#include "basecamp/cli/subcommand.hpp"

namespace tgw::basecamp {

/// Adds `linkmap FILE... --pose TOPIC[:FIELD_X,FIELD_Y] --out map.png [--idl DIR]` to `app` and returns how to run
/// it: the robot's path from the pose topic, coloured by the rate in the gateway's status, with the places where
/// samples were dropped (LinkMapBuilder, render_link_map). Each FILE is a recording, or a mission archive for the
/// drops sample by sample; a pose in two of them counts once. Exit 0; 2 for a bad flag or FILE, a pose topic absent or
/// without the fields, or no status (the message names it).
Subcommand add_linkmap_command(CLI::App& app);

}  // namespace tgw::basecamp
