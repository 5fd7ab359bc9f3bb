// make_sensor(): the one place that turns a SPEC of DESIGN section 6 into a sensor.
#include <string_view>

#include "gateway/core/config_error.hpp"
#include "sensor/bit_rate.hpp"
#include "sensor/fixed_sensor.hpp"
#include "sensor/qdisc_sensor.hpp"
#include "sensor/rate_sensor.hpp"
#include "sensor/trace_sensor.hpp"

namespace tgw::sensor {

namespace {

constexpr const char* KNOWN_SPECS = "fixed:BPS, trace:FILE, qdisc:IFACE, nl80211:IFACE[:PEER_MAC], wireless:IFACE";

[[noreturn]] void fail(const std::string& spec, const std::string& what) {
    throw core::ConfigError("sensor " + spec + ": " + what);
}

std::unique_ptr<RateSensor> make_fixed(const std::string& spec, std::string_view arg) {
    const auto rate = parse_bit_rate(arg);
    if (!rate)
        fail(spec, "'" + std::string(arg) + "' is not a bit rate (for example 20000, 20k, 1.5M)");
    if (*rate <= 0.0)
        fail(spec, "the rate must be above 0 bit/s");
    return std::make_unique<FixedSensor>(*rate);
}

std::unique_ptr<RateSensor> make_trace(const std::string& spec, std::string_view arg, const core::Clock& clock) {
    if (arg.empty())
        fail(spec, "no trace file given (trace:FILE)");
    const std::string file(arg);
    // load_rate_trace's message names the file and line; prefix the spec so the flag is named too.
    try {
        return std::make_unique<TraceSensor>(load_rate_trace(file), file, clock);
    } catch (const core::ConfigError& e) {
        fail(spec, e.what());
    }
}

std::unique_ptr<RateSensor> make_qdisc(const std::string& spec, std::string_view arg) {
    try {
        return std::make_unique<QdiscSensor>(std::string(arg));
    } catch (const core::ConfigError& e) {
        fail(spec, e.what());
    }
}

}  // namespace

std::unique_ptr<RateSensor> make_sensor(const std::string& spec, const core::Clock& clock) {
    if (spec.empty())
        throw core::ConfigError(std::string("sensor: empty SPEC, expected one of ") + KNOWN_SPECS);
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
    if (kind == "nl80211" || kind == "wireless")
        fail(spec, "not implemented yet");
    fail(spec, "unknown kind '" + std::string(kind) + "', expected one of " + KNOWN_SPECS);
}

}  // namespace tgw::sensor
