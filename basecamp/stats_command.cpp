#include "basecamp/stats_command.hpp"

#include <unistd.h>

#include <chrono>
#include <ctime>
#include <iostream>
#include <memory>

#include "base/peer_transport.hpp"
#include "basecamp/recorder.hpp"
#include "basecamp/topic_stats.hpp"

namespace tgw::basecamp {

namespace {

struct StatsOptions {
    int domain = 1;
    base::PeerTransport transport;
    double window_s = 10.0;
    bool once = false;
    double duration_s = 0.0;
};

std::int64_t wall_now_ns() {
    return base::to_ns(base::WallClock::now());
}

int run_stats(const StatsOptions& options) {
    TopicStats stats(base::from_seconds(options.window_s));
    // An observer: it sends no receiver reports, so the gateways' view of the link is the recorder's or relay's.
    Recorder subscriber(options.domain, options.transport, stats, base::Duration::zero());
    stop_on_signals();
    if (options.once) {
        subscriber.run(base::from_seconds(options.window_s), stop_requested());
        print_stats_table(std::cout, stats.rows(wall_now_ns()));
        return 0;
    }
    const bool terminal = isatty(STDOUT_FILENO) != 0;
    const auto end = options.duration_s > 0 ? base::SteadyClock::now() + base::from_seconds(options.duration_s)
                                            : base::SteadyTime::max();
    while (!stop_requested().load() && base::SteadyClock::now() < end) {
        subscriber.run(std::chrono::seconds(1), stop_requested());
        const std::time_t now = std::time(nullptr);
        char clock[16];
        std::strftime(clock, sizeof clock, "%H:%M:%S", std::localtime(&now));
        if (terminal) {
            std::cout << "\x1b[H\x1b[2J";  // one screen, redrawn
        }
        std::cout << "tm-basecamp stats: domain " << options.domain << ", last " << options.window_s << " s, " << clock
                  << "\n";
        print_stats_table(std::cout, stats.rows(wall_now_ns()));
        std::cout << (terminal ? "" : "\n") << std::flush;
    }
    return 0;
}

}  // namespace

Subcommand add_stats_command(CLI::App& app) {
    auto options = std::make_shared<StatsOptions>();
    CLI::App* command = app.add_subcommand(
        "stats",
        "every topic of a domain at once: Hz, bit/s, mean and p99 transmission time, % within TTL, samples "
        "logged on the robot; refreshed every second");
    command->add_option("--domain", options->domain, "DDS domain id (the WAN domain, or the camp's behind a relay)")
        ->check(CLI::Range(0, 232))
        ->capture_default_str();
    command->add_option("--peer", options->transport.peers,
                        "IPv4 address of the robot (repeatable): UDP unicast only, no multicast, no shared memory");
    command->add_option("--interface", options->transport.interface,
                        "interface name or IPv4 address to bind every socket to");
    command->add_option("--window", options->window_s, "seconds of samples each line is computed over")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    command->add_flag("--once", options->once, "collect for one window, print one table and exit (for scripts)");
    command->add_option("--duration", options->duration_s, "seconds to run; until Ctrl-C without it")
        ->check(CLI::PositiveNumber);
    return {command, [options] { return run_stats(*options); }};
}

}  // namespace tgw::basecamp
