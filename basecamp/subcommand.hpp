// How tm-basecamp's subcommands that live in files of their own plug into main: each adds itself to the app
// and hands back how to run it once the command line is parsed.
#pragma once

#include <CLI/CLI.hpp>

#include <atomic>
#include <functional>

namespace tgw::basecamp {

struct Subcommand {
    CLI::App* command = nullptr;
    /// Runs the parsed command and returns the exit code. May throw base::ConfigError (exit 2, message printed).
    std::function<int()> run;
};

/// True once SIGINT or SIGTERM came after stop_on_signals(): long commands then end cleanly, their files whole.
const std::atomic<bool>& stop_requested();
void stop_on_signals();

}  // namespace tgw::basecamp
