#pragma once

#include <stdexcept>
#include <string>

namespace tgw::base {

/// The one exception type of the project, thrown only while starting up. Its message names the flag, file
/// or line at fault; main() prints it and exits 2.
class ConfigError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

}  // namespace tgw::base
