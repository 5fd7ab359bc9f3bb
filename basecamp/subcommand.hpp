// How tm-basecamp's subcommands that live in files of their own plug into main: each adds itself to the app
// and hands back how to run it once the command line is parsed.
#pragma once

#include <CLI/CLI.hpp>

#include <atomic>
#include <functional>

#include "base/peer_transport.hpp"

namespace tgw::basecamp {

struct Subcommand {
    CLI::App* command = nullptr;
    /// Runs the parsed command and returns the exit code. May throw base::ConfigError (exit 2, message printed).
    std::function<int()> run;
};

/// Where a live tool (stats, status, echo) subscribes: the domain, and the link transport as `record` has it.
struct DomainOptions {
    int domain = 1;
    base::PeerTransport transport;
};

/// Adds --domain, --peer and --interface to `command` for `options`, which must outlive the app.
void add_domain_options(CLI::App& command, DomainOptions& options);

/// True once SIGINT or SIGTERM came after stop_on_signals(): long commands then end cleanly, their files whole.
const std::atomic<bool>& stop_requested();
void stop_on_signals();

}  // namespace tgw::basecamp
