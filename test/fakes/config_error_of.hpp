#pragma once

#include <string>

#include "gateway/core/config_error.hpp"

namespace tgw::test {

/// The core::ConfigError message `action` throws, or "<no error>".
template <typename F>
std::string config_error_of(F&& action) {
    try {
        action();
    } catch (const core::ConfigError& e) {
        return e.what();
    }
    return "<no error>";
}

}  // namespace tgw::test
