#include "sensor/link_quality_table.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "gateway/core/config_error.hpp"
#include "sensor/bit_rate.hpp"

namespace tgw::sensor {

LinkQualityTable LinkQualityTable::default_table() {
    return LinkQualityTable({{0, 500e3}, {10, 1e6}, {20, 2.5e6}, {30, 5e6}, {40, 12e6}, {50, 18e6}, {60, 25e6}});
}

std::optional<double> LinkQualityTable::rate_for(double quality) const {
    const auto above = std::upper_bound(rows_.begin(), rows_.end(), quality,
                                        [](double q, const Row& row) { return q < row.min_quality; });
    if (above == rows_.begin())
        return std::nullopt;
    return std::prev(above)->rate_bps;
}

LinkQualityTable parse_link_quality_table(std::istream& in, const std::string& file_name) {
    std::vector<LinkQualityTable::Row> rows;
    std::string line;
    std::size_t line_number = 0;
    while (std::getline(in, line)) {
        ++line_number;
        const auto fail = [&](const std::string& what) {
            throw core::ConfigError(file_name + ":" + std::to_string(line_number) + ": " + what);
        };
        if (const auto hash = line.find('#'); hash != std::string::npos)
            line.erase(hash);
        std::istringstream fields(line);
        std::string quality_text, rate_text, extra;
        if (!(fields >> quality_text))
            continue;
        if (!(fields >> rate_text) || (fields >> extra))
            fail("expected `quality bits_per_second`");
        double quality = 0.0;
        std::size_t used = 0;
        try {
            quality = std::stod(quality_text, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != quality_text.size() || !std::isfinite(quality))
            fail("quality '" + quality_text + "' is not a number");
        const auto rate = parse_bit_rate(rate_text);
        if (!rate)
            fail("rate '" + rate_text + "' is not a number of bit/s");
        if (*rate < 0.0)
            fail("rate " + rate_text + " is negative");
        if (!rows.empty() && quality <= rows.back().min_quality)
            fail("quality " + quality_text + " is not above the previous row's");
        rows.push_back({quality, *rate});
    }
    if (in.bad())
        throw core::ConfigError(file_name + ": read error after line " + std::to_string(line_number));
    if (rows.empty())
        throw core::ConfigError(file_name + ": no row; expected lines of `quality bits_per_second`");
    return LinkQualityTable(std::move(rows));
}

LinkQualityTable load_link_quality_table(const std::string& path) {
    std::ifstream in(path);
    if (!in)
        throw core::ConfigError(path + ": cannot open: " + std::strerror(errno));
    return parse_link_quality_table(in, path);
}

}  // namespace tgw::sensor
