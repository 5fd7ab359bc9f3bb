#include "gateway/apps/tm_robot_sim/survey_route.hpp"

#include <cmath>

namespace tgw::robot_sim {

namespace {

constexpr double WIDTH_M = 240, HEIGHT_M = 120, SPEED_M_S = 12;
constexpr double CAMP_RATE_BPS = 70'000, FAR_RATE_BPS = 10'000, FALL_M = 150;
constexpr double HILL_X_M = 200, HILL_Y_M = 100, HILL_RADIUS_M = 50, SHADOW_FACTOR = 0.4;

}  // namespace

Pose survey_pose(double seconds) {
    const double lap = 2 * (WIDTH_M + HEIGHT_M);
    double along = std::fmod(seconds * SPEED_M_S, lap);
    if (along < WIDTH_M)
        return {along, 0, 0};
    along -= WIDTH_M;
    if (along < HEIGHT_M)
        return {WIDTH_M, along, M_PI / 2};
    along -= HEIGHT_M;
    if (along < WIDTH_M)
        return {WIDTH_M - along, HEIGHT_M, M_PI};
    along -= WIDTH_M;
    return {0, HEIGHT_M - along, -M_PI / 2};
}

double field_rate_bps(const Pose& pose) {
    const double distance = std::hypot(pose.x, pose.y);
    double rate = FAR_RATE_BPS + (CAMP_RATE_BPS - FAR_RATE_BPS) * std::exp(-distance / FALL_M);
    if (std::hypot(pose.x - HILL_X_M, pose.y - HILL_Y_M) < HILL_RADIUS_M)
        rate *= SHADOW_FACTOR;
    return rate;
}

void write_field_trace(std::ostream& out, double seconds) {
    out << "# the survey route's simulated radio field (tm-robot-sim --field-trace): seconds bits_per_second\n";
    for (int t = 0; t <= static_cast<int>(std::ceil(seconds)); ++t)
        out << t << " " << static_cast<long>(std::lround(field_rate_bps(survey_pose(t)))) << "\n";
}

}  // namespace tgw::robot_sim
