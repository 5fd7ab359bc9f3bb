#include "sensor/proc_net_wireless.hpp"

#include <charconv>
#include <cmath>
#include <optional>
#include <sstream>
#include <string_view>

namespace tgw::sensor {

namespace {

/// "54." or "-256" or "54": the kernel appends '.' to a value updated since the last read.
std::optional<double> parse_value(std::string_view text) {
    if (!text.empty() && text.back() == '.')
        text.remove_suffix(1);
    double value = 0.0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(value))
        return std::nullopt;
    return value;
}

}  // namespace

WirelessTable parse_proc_net_wireless(std::istream& in) {
    WirelessTable table;
    std::string line;
    std::size_t line_number = 0;
    while (std::getline(in, line)) {
        ++line_number;
        const auto colon = line.find(':');
        // The header lines ("Inter-| sta-|...", " face | tus |...") hold no colon.
        if (colon == std::string::npos)
            continue;
        const auto fail = [&](const std::string& what) {
            table.error = "line " + std::to_string(line_number) + ": " + what;
            table.interfaces.clear();
            return table;
        };
        std::istringstream name_stream(line.substr(0, colon));
        WirelessStatus status;
        if (!(name_stream >> status.interface))
            return fail("no interface name before ':'");
        std::istringstream fields(line.substr(colon + 1));
        std::string status_word, link, level, noise;
        if (!(fields >> status_word >> link >> level >> noise))
            return fail("expected `" + status.interface + ": status link level noise ...`");
        const auto link_value = parse_value(link);
        const auto level_value = parse_value(level);
        const auto noise_value = parse_value(noise);
        if (!link_value || !level_value || !noise_value)
            return fail("quality of " + status.interface + " is not numbers: " + link + " " + level + " " + noise);
        status.link_quality = *link_value;
        status.level_dbm = *level_value;
        status.noise_dbm = *noise_value;
        table.interfaces.push_back(std::move(status));
    }
    if (in.bad()) {
        table.error = "read error after line " + std::to_string(line_number);
        return table;
    }
    table.ok = true;
    return table;
}

}  // namespace tgw::sensor
