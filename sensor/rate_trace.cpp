#include "sensor/rate_trace.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include "sensor/bit_rate.hpp"
#include "sensor/config_line_reader.hpp"

namespace tgw::sensor {

namespace {

/// Far beyond any mission, and well inside what a nanosecond Duration holds (292 years).
constexpr double MAX_TRACE_SECONDS = 1e9;

/// A plain number, no suffix: "1k" seconds is surely a mistake.
std::optional<double> parse_seconds(std::string_view text) {
    if (!text.empty() && text.front() == '+')
        text.remove_prefix(1);
    double value = 0.0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value, std::chars_format::general);
    if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(value))
        return std::nullopt;
    return value;
}

std::string format_seconds(base::Duration d) {
    std::ostringstream out;
    out << base::to_seconds(d);
    return out.str();
}

}  // namespace

RateTrace parse_rate_trace(std::istream& in, const std::string& file_name) {
    std::vector<RateTrace::Step> steps;
    ConfigLineReader lines(in, file_name);
    while (lines.next()) {
        const auto& fields = lines.fields();
        if (fields.size() != 2)
            lines.fail("expected `seconds bits_per_second`, got " + std::to_string(fields.size()) + " field" +
                       (fields.size() == 1 ? "" : "s"));

        const std::string time_text(fields[0]);
        const std::string rate_text(fields[1]);
        const auto seconds = parse_seconds(fields[0]);
        if (!seconds)
            lines.fail("time '" + time_text + "' is not a number of seconds");
        if (*seconds < 0.0)
            lines.fail("time " + time_text + " is negative");
        if (*seconds > MAX_TRACE_SECONDS)
            lines.fail("time " + time_text + " is beyond " + std::to_string(static_cast<long long>(MAX_TRACE_SECONDS)) +
                       " s");
        const auto rate = parse_bit_rate(rate_text);
        if (!rate)
            lines.fail("rate '" + rate_text + "' is not a number of bit/s");
        if (*rate < 0.0)
            lines.fail("rate " + rate_text + " is negative");

        const base::Duration at = base::from_seconds(*seconds);
        if (!steps.empty() && at <= steps.back().at)
            lines.fail("time " + time_text + " s is not after the previous step's " + format_seconds(steps.back().at) +
                       " s");
        steps.push_back({at, *rate});
    }
    if (steps.empty())
        lines.fail_file("no rate in the trace; expected lines of `seconds bits_per_second`");
    return RateTrace(std::move(steps));
}

RateTrace load_rate_trace(const std::string& path) {
    std::ifstream in = open_config_file(path);
    return parse_rate_trace(in, path);
}

}  // namespace tgw::sensor
