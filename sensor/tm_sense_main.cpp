// tm-sense: read a rate sensor the way the gateway does, one line per reading, as the paper's iwspy did.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <thread>

#include "base/cli_checks.hpp"
#include "base/config_error.hpp"
#include "base/utc_text.hpp"
#include "sensor/delivered_rate_check.hpp"
#include "sensor/guarded_sensor.hpp"
#include "sensor/rate_sensor.hpp"

int main(int argc, char** argv) {
    CLI::App app{"tm-sense: print a link's data rate as the gateway's sensor reads it"};
    app.set_version_flag("--version", std::string("tm-sense ") + TGW_VERSION);
    std::string spec;
    int interval_ms = 1000;
    long count = 0;
    app.add_option("--sensor", spec,
                   "fixed:BPS, trace:FILE, qdisc:IFACE, nl80211:IFACE[:PEER_MAC], wireless:IFACE[:table=FILE]")
        ->required();
    app.add_option("--interval", interval_ms, "milliseconds between readings")->check(tgw::base::positive());
    app.add_option("--count", count, "readings to print, 0 = until interrupted")->check(tgw::base::non_negative());
    // The guard the gateway can put around its sensor, to see what the budget would get.
    bool guard = false;
    tgw::sensor::GuardConfig guard_config;
    double hold_s = tgw::base::to_seconds(guard_config.hold);
    app.add_flag("--guard", guard, "hold, floor, smooth and discount the readings as the gateway's guard does");
    app.add_option("--hold", hold_s, "with --guard: seconds a failed sensor keeps its last good rate")
        ->capture_default_str();
    app.add_option("--floor", guard_config.floor_bps, "with --guard: bit/s once the hold is over")
        ->capture_default_str();
    app.add_option("--smoothing", guard_config.smoothing, "with --guard: weight of a rising reading, (0, 1]")
        ->capture_default_str();
    app.add_option("--margin", guard_config.margin, "with --guard: fraction taken off, [0, 1)")->capture_default_str();
    std::string delivered_interface;
    app.add_option("--delivered-check", delivered_interface,
                   "compare the readings with what IFACE's qdisc really delivers, capping them as the gateway does");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }

    tgw::base::SystemClock clock;
    std::unique_ptr<tgw::sensor::RateSensor> sensor;
    try {
        if (guard) {
            guard_config.hold = tgw::base::from_seconds(hold_s);
            sensor = tgw::sensor::make_guarded_sensor(spec, guard_config, clock,
                                                      [](tgw::sensor::SensorLogLevel, const std::string& message) {
                                                          std::cerr << "tm-sense: " << message << std::endl;
                                                      });
        } else {
            sensor = tgw::sensor::make_sensor(spec, clock);
        }
        if (!delivered_interface.empty()) {
            tgw::sensor::DeliveredRateSources sources;
            try {
                sources = tgw::sensor::kernel_sources(delivered_interface, {});
            } catch (const tgw::base::ConfigError& e) {
                throw tgw::base::ConfigError(std::string("delivered-check: ") + e.what());
            }
            sensor = std::make_unique<tgw::sensor::DeliveredRateCheck>(
                std::move(sensor), std::move(sources), tgw::sensor::DeliveredRateConfig{}, clock,
                [](tgw::sensor::SensorLogLevel, const std::string& message) {
                    std::cerr << "tm-sense: " << message << std::endl;
                });
        }
    } catch (const tgw::base::ConfigError& e) {
        std::cerr << "tm-sense: --" << e.what() << "\n";  // the message starts "sensor SPEC: "
        return 2;
    }

    auto next = clock.now();
    for (long i = 0; count == 0 || i < count; ++i) {
        if (i > 0) {
            next += std::chrono::milliseconds(interval_ms);
            std::this_thread::sleep_until(next);
        }
        const tgw::sensor::RateReading r = sensor->read();
        std::cout << tgw::base::utc_text(clock.wall_now(), 3) << ' ';
        if (r.ok) {
            std::cout << static_cast<long long>(r.rate_bps) << " bit/s";
            if (!r.detail.empty())
                std::cout << ' ' << r.detail;
        } else {
            std::cout << "error: " << r.error;
        }
        std::cout << std::endl;
    }
    return 0;
}
