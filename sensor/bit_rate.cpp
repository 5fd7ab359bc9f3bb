#include "sensor/bit_rate.hpp"

#include <charconv>
#include <cmath>

namespace tgw::sensor {

std::optional<double> parse_bit_rate(std::string_view text) {
    double multiplier = 1.0;
    if (!text.empty()) {
        switch (text.back()) {
            case 'k':
            case 'K':
                multiplier = 1e3;
                break;
            case 'M':
                multiplier = 1e6;
                break;
            case 'G':
                multiplier = 1e9;
                break;
            default:
                break;
        }
        if (multiplier != 1.0)
            text.remove_suffix(1);
    }
    if (text.empty())
        return std::nullopt;
    // from_chars rejects a leading '+', which people do write.
    if (text.front() == '+')
        text.remove_prefix(1);
    double value = 0.0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value, std::chars_format::general);
    if (ec != std::errc() || ptr != end || !std::isfinite(value))
        return std::nullopt;
    return value * multiplier;
}

}  // namespace tgw::sensor
