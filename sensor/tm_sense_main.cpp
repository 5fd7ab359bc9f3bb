// tm-sense: read a rate sensor the way the gateway does, one line per reading, as the paper's iwspy did.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <thread>

#include "gateway/core/config_error.hpp"
#include "sensor/rate_sensor.hpp"

namespace {

std::string wall_time_text(tgw::core::WallTime t) {
    const std::time_t seconds = tgw::core::WallClock::to_time_t(t);
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(t.time_since_epoch()).count() % 1000;
    std::tm tm{};
    gmtime_r(&seconds, &tm);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d.%03lldZ", tm.tm_year + 1900, tm.tm_mon + 1,
                  tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<long long>(ms));
    return buf;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"tm-sense: print a link's data rate as the gateway's sensor reads it"};
    app.set_version_flag("--version", std::string("tm-sense ") + TGW_VERSION);
    std::string spec;
    int interval_ms = 1000;
    long count = 0;
    app.add_option("--sensor", spec, "fixed:BPS, trace:FILE, qdisc:IFACE, ...")->required();
    app.add_option("--interval", interval_ms, "milliseconds between readings")->check(CLI::PositiveNumber);
    app.add_option("--count", count, "readings to print, 0 = until interrupted")->check(CLI::NonNegativeNumber);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }

    tgw::core::SystemClock clock;
    std::unique_ptr<tgw::sensor::RateSensor> sensor;
    try {
        sensor = tgw::sensor::make_sensor(spec, clock);
    } catch (const tgw::core::ConfigError& e) {
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
        std::cout << wall_time_text(clock.wall_now()) << ' ';
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
