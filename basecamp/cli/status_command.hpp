#pragma once

#include "basecamp/cli/subcommand.hpp"

namespace tgw::basecamp {

/// `tm-basecamp status`: the gateways' status topic (tgw/status) live, one screen refreshed every second
/// (StatusView): the sensed rate over the last minutes, queue depth per topic, drops by reason.
Subcommand add_status_command(CLI::App& app);

}  // namespace tgw::basecamp
