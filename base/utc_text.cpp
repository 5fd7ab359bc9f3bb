#include "base/utc_text.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <ctime>

namespace tgw::base {

std::string utc_text(WallTime time, int fraction_digits) {
    const std::int64_t ns = to_ns(time);
    std::int64_t seconds = ns / 1'000'000'000;
    std::int64_t fraction = ns % 1'000'000'000;
    if (fraction < 0) {
        fraction += 1'000'000'000;
        --seconds;
    }
    const int digits = std::clamp(fraction_digits, 0, 9);
    for (int i = digits; i < 9; ++i) {
        fraction /= 10;
    }
    const std::time_t t = static_cast<std::time_t>(seconds);
    std::tm utc{};
    gmtime_r(&t, &utc);
    char text[64];
    const int n = std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%02d", utc.tm_year + 1900, utc.tm_mon + 1,
                                utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec);
    if (digits > 0) {
        std::snprintf(text + n, sizeof text - static_cast<std::size_t>(n), ".%0*lldZ", digits,
                      static_cast<long long>(fraction));
    } else {
        std::snprintf(text + n, sizeof text - static_cast<std::size_t>(n), "Z");
    }
    return text;
}

}  // namespace tgw::base
