#pragma once

#include <string>

#include "base/config_error.hpp"

namespace tgw::test {

/// The base::ConfigError message `action` throws, or "<no error>".
template <typename F>
std::string config_error_of(F&& action) {
    try {
        action();
    } catch (const base::ConfigError& e) {
        return e.what();
    }
    return "<no error>";
}

}  // namespace tgw::test
