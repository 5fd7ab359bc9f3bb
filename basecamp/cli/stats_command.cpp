#include "basecamp/cli/stats_command.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <iostream>
#include <memory>

#include "basecamp/capture/recorder.hpp"
#include "basecamp/cli/live_screen.hpp"
#include "basecamp/live/topic_stats.hpp"
#include "wire/gateway_topics.hpp"

namespace tgw::basecamp {

namespace {

struct StatsOptions : DomainOptions {
    double window_s = 10.0;
    bool once = false;
    double duration_s = 0.0;
};

/// How long --once waits for the robot's first sample before its window starts.
constexpr auto ONCE_DISCOVERY_WAIT = std::chrono::seconds(20);

std::int64_t wall_now_ns() {
    return base::to_ns(base::WallClock::now());
}

bool received_robot_sample(const Recorder& subscriber) {
    const auto received = subscriber.received();
    return std::any_of(received.begin(), received.end(),
                       [](const auto& topic) { return topic.second > 0 && !wire::is_gateway_topic(topic.first); });
}

int run_stats(const StatsOptions& options) {
    TopicStats stats(base::from_seconds(options.window_s));
    // An observer: it sends no receiver reports, so the gateways' view of the link is the recorder's or relay's.
    Recorder subscriber(options.domain, options.transport, stats, base::Duration::zero(),
                        security_files(options.security_dir));
    stop_on_signals();
    if (options.once) {
        // The window starts with the first sample of the robot's: discovery on a link takes a few seconds, and a
        // window that began before would under-count every rate. Behind a gateway its status comes first, before
        // any publisher on the robot may have started.
        const auto give_up = base::SteadyClock::now() + ONCE_DISCOVERY_WAIT;
        while (!received_robot_sample(subscriber) && !stop_requested().load() && base::SteadyClock::now() < give_up)
            subscriber.run(std::chrono::milliseconds(100), stop_requested());
        subscriber.run(base::from_seconds(options.window_s), stop_requested());
        print_stats_table(std::cout, stats.rows(wall_now_ns()));
        return 0;
    }
    run_live_screen(
        base::from_seconds(options.duration_s), [&](base::Duration slice) { subscriber.run(slice, stop_requested()); },
        [&](std::ostream& out) {
            const std::time_t now = std::time(nullptr);
            char clock[16];
            std::strftime(clock, sizeof clock, "%H:%M:%S", std::localtime(&now));
            out << "tm-basecamp stats: domain " << options.domain << ", last " << options.window_s << " s, " << clock
                << "\n";
            print_stats_table(out, stats.rows(wall_now_ns()));
        });
    return 0;
}

}  // namespace

Subcommand add_stats_command(CLI::App& app) {
    auto options = std::make_shared<StatsOptions>();
    CLI::App* command = app.add_subcommand(
        "stats",
        "every topic of a domain at once: Hz, bit/s, mean and p99 transmission time, % within TTL, samples "
        "logged on the robot; refreshed every second");
    add_domain_options(*command, *options);
    command->add_option("--window", options->window_s, "seconds of samples each line is computed over")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    command->add_flag("--once", options->once,
                      "collect for one window from the first sample of a robot's topic (the gateway's own, tgw/..., "
                      "do not start it; up to 20 s), print one table and exit (for scripts)");
    command->add_option("--duration", options->duration_s, "seconds to run; until Ctrl-C without it")
        ->check(CLI::PositiveNumber);
    return {command, [options] { return run_stats(*options); }};
}

}  // namespace tgw::basecamp
