#include "basecamp/subcommand.hpp"

#include <csignal>

namespace tgw::basecamp {

namespace {

std::atomic<bool> g_stop{false};

void on_signal(int) {
    g_stop.store(true);
}

}  // namespace

void add_domain_options(CLI::App& command, DomainOptions& options) {
    command.add_option("--domain", options.domain, "DDS domain id (the WAN domain, or the camp's behind a relay)")
        ->check(CLI::Range(0, 232))
        ->capture_default_str();
    // One value per flag: a repeated flag adds one, and a positional argument after it stays one.
    command
        .add_option("--peer", options.transport.peers,
                    "IPv4 address of the robot (repeatable): UDP unicast only, no multicast, no shared memory")
        ->allow_extra_args(false);
    command.add_option("--interface", options.transport.interface,
                       "interface name or IPv4 address to bind every socket to");
}

const std::atomic<bool>& stop_requested() {
    return g_stop;
}

void stop_on_signals() {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
}

}  // namespace tgw::basecamp
