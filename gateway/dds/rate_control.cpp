#include "gateway/dds/rate_control.hpp"

#include <chrono>
#include <cmath>

#include "core/granted_rate.hpp"
#include "gateway/dds/grant_reader.hpp"
#include "gateway/dds/wan_router.hpp"
#include "gateway/log/robot_log.hpp"

namespace tgw::dds {

namespace {

// The on-robot log's link_rates: a row when the rate changes by this fraction, else one a period at most.
constexpr double RATE_LOG_CHANGE = 0.02;
constexpr auto RATE_LOG_PERIOD = std::chrono::seconds(1);

}  // namespace

RateControl::RateControl(core::ForwardingLoop& loop, WanRouter& wan, log::RobotLog* log, double budget_fraction,
                         double initial_bps, const base::Clock& clock)
    : loop_(loop), wan_(wan), log_(log), budget_fraction_(budget_fraction), clock_(clock), sensed_bps_(initial_bps) {}

void RateControl::sensed(double bps) {
    sensed_bps_.store(bps);
    apply();
}

bool RateControl::set_link_up(bool up) {
    const bool was_up = link_up_.exchange(up);
    apply();
    return was_up;
}

void RateControl::set_rebinding(bool rebinding) {
    rebinding_.store(rebinding);
    apply();
}

void RateControl::set_least_share(double bps) {
    least_share_bps_.store(bps);
    apply();
}

void RateControl::apply() {
    // Logged here, not where a reading comes: under grants the rate the gateway goes by moves with each grant.
    const double sensed = sensed_bps_.load();
    double rate =
        grants_ != nullptr ? core::granted_rate_bps(sensed, grants_->view(), least_share_bps_.load()) : sensed;
    if (!link_up_.load() || rebinding_.load()) {
        rate = 0;
    }
    double commands_bps = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        commands_rate_.update(clock_.now(), commands_bytes_.load(std::memory_order_relaxed));
        commands_bps = commands_rate_.bps(clock_.now());
    }
    loop_.set_rate(rate, commands_bps);
    if (RepairDesk* desk = wan_.repair_desk()) {
        desk->pace_fragments(core::paces_fragments_at(rate));
    }
    log_rate(sensed, rate);
}

void RateControl::log_rate(double sensed_bps, double rate_bps) {
    if (log_ == nullptr)
        return;
    // Every change of 2 % or more, and once a second otherwise: the link's history at a row a second or so.
    const auto now = base::SteadyClock::now();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto moved = [](double is, double was) { return std::abs(is - was) >= RATE_LOG_CHANGE * was; };
        const bool changed = moved(sensed_bps, logged_sensed_bps_) || moved(rate_bps, logged_rate_bps_);
        if (!changed && now - logged_at_ < RATE_LOG_PERIOD)
            return;
        logged_sensed_bps_ = sensed_bps;
        logged_rate_bps_ = rate_bps;
        logged_at_ = now;
    }
    log_->append_rate({base::WallClock::now(), sensed_bps, rate_bps * budget_fraction_});
}

}  // namespace tgw::dds
