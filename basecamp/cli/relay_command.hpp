// tm-basecamp relay: the camp's one participant on the WAN domain (Relay), from the command line.
#pragma once

#include <CLI/CLI.hpp>

#include "basecamp/cli/subcommand.hpp"

namespace tgw::basecamp {

/// Adds `relay --domain N --local-domain N [--peer ADDR]... [--interface IFACE] ...` to `app`. Its run relays
/// until --duration or SIGINT/SIGTERM and prints what it relayed; with --interface, it makes the relay anew on
/// the interface's new address when the one it was bound to goes (a DHCP lease, the camp moved to another radio).
/// Throws base::ConfigError (exit 2) naming the flag at fault.
Subcommand add_relay_command(CLI::App& app);

}  // namespace tgw::basecamp
