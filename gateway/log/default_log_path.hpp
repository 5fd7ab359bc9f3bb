#pragma once

#include <string>

namespace tgw::log {

/// Where telemetry-gateway keeps its on-robot log when not told (no --log): robot-log.db in the XDG state
/// directory, $XDG_STATE_HOME/telemetry-gateway/ (state that outlives a restart and is nobody's document), else
/// $HOME/.local/state/telemetry-gateway/, else the working directory. Arguments: the two variables, null when unset;
/// a relative XDG_STATE_HOME is ignored, as the XDG base directory spec asks.
std::string default_log_path(const char* xdg_state_home, const char* home);

}  // namespace tgw::log
