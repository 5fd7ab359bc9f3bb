// The rate the gateway's schedule budgets with, from everything that moves it.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>

#include "base/clock.hpp"
#include "core/forwarding_loop.hpp"
#include "core/sent_rate.hpp"

namespace tgw::log {
class RobotLog;
}

namespace tgw::dds {

class GrantReader;
class WanRouter;

/// The sensor's last rate, or with --channel-grants core::granted_rate_bps: the base camp's grant (never below the
/// least share of the last status), or a newcomer's share before the first; 0 while the WAN interface is down or
/// the WAN participant is made anew (a sensor may still read the shaper's or the radio's last rate). On a
/// half-duplex link the camp's commands take their part of it steadily. Each change goes to the loop and the WAN's
/// repair desk, and to the on-robot log's link_rates. Thread-safe: readings, grants and the link's state come from
/// threads of their own.
class RateControl {
  public:
    RateControl(core::ForwardingLoop& loop, WanRouter& wan, log::RobotLog* log, double budget_fraction,
                double initial_bps, const base::Clock& clock);

    /// With --channel-grants; before the first grant can come.
    void set_grants(const GrantReader* grants) { grants_ = grants; }
    /// A new reading of the sensor's rate.
    void sensed(double bps);
    /// The WAN interface went up or down; returns whether it was up before.
    bool set_link_up(bool up);
    bool link_up() const { return link_up_.load(); }
    /// The WAN participant is being made anew (true) or is done (false).
    void set_rebinding(bool rebinding);
    /// The least share the last status asked for (core::least_share_bps).
    void set_least_share(double bps);
    /// The camp's commands (--duplex half) put `frame_bytes` on the link.
    void commands_charged(std::uint64_t frame_bytes) {
        commands_bytes_.fetch_add(frame_bytes, std::memory_order_relaxed);
    }
    /// Works the rate out anew and applies it.
    void apply();

  private:
    /// Writes the sensor's rate and the budget of the rate the gateway goes by (`rate_bps`: under grants its
    /// grant, not the sensor's) to the log's link_rates, at most once a second unless either changed.
    void log_rate(double sensed_bps, double rate_bps);

    core::ForwardingLoop& loop_;
    WanRouter& wan_;
    log::RobotLog* log_;
    const double budget_fraction_;
    const base::Clock& clock_;
    const GrantReader* grants_ = nullptr;
    std::atomic<double> sensed_bps_;  ///< the sensor's last rate; the initial rate before the first
    std::atomic<bool> link_up_{true};
    std::atomic<bool> rebinding_{false};
    std::atomic<double> least_share_bps_{0.0};
    std::atomic<std::uint64_t> commands_bytes_{0};
    std::mutex mutex_;
    core::SentRate commands_rate_;     // under mutex_
    double logged_sensed_bps_ = -1.0;  ///< the last row written to the log's link_rates; under mutex_
    double logged_rate_bps_ = -1.0;
    base::SteadyTime logged_at_{};
};

}  // namespace tgw::dds
