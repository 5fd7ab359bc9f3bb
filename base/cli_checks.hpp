#pragma once

// Checks for the programs' numeric flags whose messages an operator can read: CLI11's own PositiveNumber says
// "Value 0 not in range 0.000000 to 1797693134862315708145274237317043567980...".
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <string>

namespace tgw::base {

/// A number in [low, high] (`high` may be infinite); the message says what is expected and what was given, and
/// --help shows `brief` after the type.
inline CLI::Validator number_in(double low, double high, std::string expected, std::string brief) {
    return CLI::Validator(
        [low, high, expected](std::string& text) -> std::string {
            double value = 0.0;
            char rest = 0;
            if (std::sscanf(text.c_str(), "%lf%c", &value, &rest) != 1 || !(value >= low && value <= high)) {
                return "expected " + expected + ", got '" + text + "'";
            }
            return {};
        },
        brief);
}

/// A number above 0.
inline CLI::Validator positive() {
    return number_in(std::nextafter(0.0, 1.0), HUGE_VAL, "a number above 0", "POSITIVE");
}

/// A number of at least 0.
inline CLI::Validator non_negative() {
    return number_in(0.0, HUGE_VAL, "a number >= 0", "NONNEGATIVE");
}

}  // namespace tgw::base
