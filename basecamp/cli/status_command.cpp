#include "basecamp/cli/status_command.hpp"

#include <iostream>
#include <memory>

#include "basecamp/capture/recorder.hpp"
#include "basecamp/cli/live_screen.hpp"
#include "basecamp/live/status_view.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {

namespace {

struct StatusOptions : DomainOptions {
    double minutes = 5.0;
    bool once = false;
    double timeout_s = 60.0;
    double duration_s = 0.0;
};

int run_status(const StatusOptions& options) {
    StatusView view(base::from_seconds(60.0 * options.minutes));
    Recorder subscriber(options.domain, options.transport, view, base::Duration::zero(),
                        security_files(options.security_dir));
    subscriber.only({wire::STATUS_TOPIC});
    stop_on_signals();
    const auto now_ns = [] { return base::to_ns(base::WallClock::now()); };
    if (options.once) {
        // On a slow link a status comes every 10 s or more (it takes at most 2 % of the rate).
        const auto give_up = base::SteadyClock::now() + base::from_seconds(options.timeout_s);
        while (view.statuses() == 0 && !stop_requested().load() && base::SteadyClock::now() < give_up) {
            subscriber.run(std::chrono::milliseconds(200), stop_requested());
        }
        if (view.statuses() == 0) {
            std::cerr << "tm-basecamp status: no status on " << wire::STATUS_TOPIC << " of domain " << options.domain
                      << " within " << options.timeout_s << " s (--timeout)\n";
            return 1;
        }
        view.render(std::cout, now_ns());
        return 0;
    }
    run_live_screen(
        base::from_seconds(options.duration_s), [&](base::Duration slice) { subscriber.run(slice, stop_requested()); },
        [&](std::ostream& out) { view.render(out, now_ns()); });
    return 0;
}

}  // namespace

Subcommand add_status_command(CLI::App& app) {
    auto options = std::make_shared<StatusOptions>();
    CLI::App* command = app.add_subcommand(
        "status",
        "the gateways' status (tgw/status) live: sensed rate over the last minutes, queue depth per topic, "
        "drops by reason; one screen refreshed every second");
    add_domain_options(*command, *options);
    command->add_option("--minutes", options->minutes, "how far back the rate graph goes")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    command->add_flag("--once", options->once, "wait for a status, print one screen and exit (for scripts)");
    command->add_option("--timeout", options->timeout_s, "with --once: seconds to wait for a status (exit 1 after)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    command->add_option("--duration", options->duration_s, "seconds to run; until Ctrl-C without it")
        ->check(CLI::PositiveNumber);
    return {command, [options] { return run_status(*options); }};
}

}  // namespace tgw::basecamp
