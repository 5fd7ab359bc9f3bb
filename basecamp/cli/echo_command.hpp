// tm-basecamp echo TOPIC: every sample of one topic as it arrives, decoded field by field.
#pragma once

#include <CLI/CLI.hpp>

#include "basecamp/cli/subcommand.hpp"

namespace tgw::basecamp {

/// Adds `echo TOPIC [--domain N] [--peer ADDR]... [--interface IFACE] [--count N] [--json] [--idl DIR]...
/// [--timeout S]` to `app`. Its run exits 0 when --count samples were printed (or at SIGINT/SIGTERM, or after
/// --timeout without --count), 1 when --timeout passed before --count samples came, and throws
/// base::ConfigError (exit 2) naming the flag, file and line of a bad --idl file or a refused --domain, --peer
/// or --interface.
Subcommand add_echo_command(CLI::App& app);

}  // namespace tgw::basecamp
