// make_sensor(): the one place that turns a SPEC of docs/design.md §6 into a sensor.
#include <optional>
#include <string_view>

#include "base/config_error.hpp"
#include "sensor/bit_rate.hpp"
#include "sensor/fixed_sensor.hpp"
#include "sensor/guarded_sensor.hpp"
#include "sensor/link_quality_table.hpp"
#include "sensor/nl80211_sensor.hpp"
#include "sensor/qdisc_sensor.hpp"
#include "sensor/rate_sensor.hpp"
#include "sensor/trace_sensor.hpp"
#include "sensor/wireless_sensor.hpp"

namespace tgw::sensor {

namespace {

constexpr const char* KNOWN_SPECS =
    "fixed:BPS, trace:FILE, qdisc:IFACE, nl80211:IFACE[:PEER_MAC], wireless:IFACE[:table=FILE]";

[[noreturn]] void fail(const std::string& spec, const std::string& what) {
    throw base::ConfigError("sensor " + spec + ": " + what);
}

std::unique_ptr<RateSensor> make_fixed(const std::string& spec, std::string_view arg) {
    const auto rate = parse_bit_rate(arg);
    if (!rate)
        fail(spec, "'" + std::string(arg) + "' is not a bit rate (for example 20000, 20k, 1.5M)");
    if (*rate <= 0.0)
        fail(spec, "the rate must be above 0 bit/s");
    return std::make_unique<FixedSensor>(*rate);
}

std::unique_ptr<RateSensor> make_trace(const std::string& spec, std::string_view arg, const base::Clock& clock) {
    if (arg.empty())
        fail(spec, "no trace file given (trace:FILE)");
    const std::string file(arg);
    // load_rate_trace's message names the file and line; prefix the spec so the flag is named too.
    try {
        return std::make_unique<TraceSensor>(load_rate_trace(file), file, clock);
    } catch (const base::ConfigError& e) {
        fail(spec, e.what());
    }
}

std::unique_ptr<RateSensor> make_qdisc(const std::string& spec, std::string_view arg) {
    try {
        return std::make_unique<QdiscSensor>(std::string(arg));
    } catch (const base::ConfigError& e) {
        fail(spec, e.what());
    }
}

/// `IFACE[:PEER_MAC]`: the MAC holds colons itself, so the interface ends at the first one.
std::unique_ptr<RateSensor> make_nl80211(const std::string& spec, std::string_view arg) {
    const auto colon = arg.find(':');
    const std::string interface(arg.substr(0, colon));
    std::optional<MacAddress> peer;
    if (colon != std::string_view::npos) {
        const std::string_view mac = arg.substr(colon + 1);
        peer = parse_mac(mac);
        if (!peer)
            fail(spec, "'" + std::string(mac) + "' is not a MAC address (for example 02:00:00:00:01:00)");
    }
    try {
        return std::make_unique<Nl80211Sensor>(interface, peer);
    } catch (const base::ConfigError& e) {
        fail(spec, e.what());
    }
}

/// `IFACE[:table=FILE]`.
std::unique_ptr<RateSensor> make_wireless(const std::string& spec, std::string_view arg) {
    const auto colon = arg.find(':');
    const std::string interface(arg.substr(0, colon));
    std::string table_file;
    if (colon != std::string_view::npos) {
        constexpr std::string_view TABLE = "table=";
        const std::string_view option = arg.substr(colon + 1);
        if (option.substr(0, TABLE.size()) != TABLE || option.size() == TABLE.size())
            fail(spec, "unknown option '" + std::string(option) + "', expected wireless:IFACE[:table=FILE]");
        table_file = std::string(option.substr(TABLE.size()));
    }
    try {
        auto sensor = std::make_unique<WirelessSensor>(
            interface, table_file.empty() ? LinkQualityTable::default_table() : load_link_quality_table(table_file));
        sensor->set_table_name(table_file);
        return sensor;
    } catch (const base::ConfigError& e) {
        fail(spec, e.what());
    }
}

}  // namespace

std::unique_ptr<RateSensor> make_sensor(const std::string& spec, const base::Clock& clock) {
    if (spec.empty())
        throw base::ConfigError(std::string("sensor: empty SPEC, expected one of ") + KNOWN_SPECS);
    const auto colon = spec.find(':');
    if (colon == std::string::npos)
        fail(spec, std::string("expected KIND:ARGUMENT, one of ") + KNOWN_SPECS);
    const std::string_view kind = std::string_view(spec).substr(0, colon);
    const std::string_view arg = std::string_view(spec).substr(colon + 1);
    if (kind == "fixed")
        return make_fixed(spec, arg);
    if (kind == "trace")
        return make_trace(spec, arg, clock);
    if (kind == "qdisc")
        return make_qdisc(spec, arg);
    if (kind == "nl80211")
        return make_nl80211(spec, arg);
    if (kind == "wireless")
        return make_wireless(spec, arg);
    fail(spec, "unknown kind '" + std::string(kind) + "', expected one of " + KNOWN_SPECS);
}

std::unique_ptr<RateSensor> make_guarded_sensor(const std::string& spec, const GuardConfig& config,
                                                const base::Clock& clock, SensorLog log) {
    // Before the sensor is built: a bad guard should not cost a netlink round trip, and names the spec as given.
    if (auto error = config.validate(); !error.empty())
        fail(spec, error);
    return std::make_unique<GuardedSensor>(make_sensor(spec, clock), config, clock, std::move(log));
}

}  // namespace tgw::sensor
