#include "sensor/link_quality_table.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "sensor/bit_rate.hpp"
#include "sensor/config_line_reader.hpp"

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
    ConfigLineReader lines(in, file_name);
    while (lines.next()) {
        if (lines.fields().size() != 2)
            lines.fail("expected `quality bits_per_second`");
        const std::string quality_text(lines.fields()[0]);
        const std::string rate_text(lines.fields()[1]);
        double quality = 0.0;
        std::size_t used = 0;
        try {
            quality = std::stod(quality_text, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != quality_text.size() || !std::isfinite(quality))
            lines.fail("quality '" + quality_text + "' is not a number");
        const auto rate = parse_bit_rate(rate_text);
        if (!rate)
            lines.fail("rate '" + rate_text + "' is not a number of bit/s");
        if (*rate < 0.0)
            lines.fail("rate " + rate_text + " is negative");
        if (!rows.empty() && quality <= rows.back().min_quality)
            lines.fail("quality " + quality_text + " is not above the previous row's");
        rows.push_back({quality, *rate});
    }
    if (rows.empty())
        lines.fail_file("no row; expected lines of `quality bits_per_second`");
    return LinkQualityTable(std::move(rows));
}

LinkQualityTable load_link_quality_table(const std::string& path) {
    std::ifstream in = open_config_file(path);
    return parse_link_quality_table(in, path);
}

}  // namespace tgw::sensor
