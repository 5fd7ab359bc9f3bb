#include "basecamp/subcommand.hpp"

#include <csignal>

namespace tgw::basecamp {

namespace {

std::atomic<bool> g_stop{false};

void on_signal(int) {
    g_stop.store(true);
}

}  // namespace

const std::atomic<bool>& stop_requested() {
    return g_stop;
}

void stop_on_signals() {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
}

}  // namespace tgw::basecamp
