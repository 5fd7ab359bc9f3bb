#include "gateway/log/default_log_path.hpp"

namespace tgw::log {

namespace {
constexpr const char* FILE_NAME = "robot-log.db";
constexpr const char* APP_DIR = "/telemetry-gateway/";

bool absolute(const char* path) {
    return path != nullptr && path[0] == '/';
}
}  // namespace

std::string default_log_path(const char* xdg_state_home, const char* home) {
    if (absolute(xdg_state_home)) {
        return std::string(xdg_state_home) + APP_DIR + FILE_NAME;
    }
    if (absolute(home)) {
        return std::string(home) + "/.local/state" + APP_DIR + FILE_NAME;
    }
    return FILE_NAME;
}

}  // namespace tgw::log
