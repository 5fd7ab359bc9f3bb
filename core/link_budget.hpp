#pragma once

#include <algorithm>
#include <cstdint>

#include "base/time.hpp"

namespace tgw::core {

/// The link as the gateway models it: non-preemptive, one sample on the wire at a time, at the sensed rate.
/// Sending charges the sample's wire time; the link is free again once what was charged has drained. A
/// short lead lets the next sample be handed to the kernel just before the previous one finishes, so the
/// link never idles while the queue holds something (a token bucket whose depth is lead x rate).
class LinkBudget {
  public:
    LinkBudget(double rate_bps, base::Duration lead);

    /// Follow a new sensed rate. What was already charged keeps its old wire time.
    void set_rate(double rate_bps) { rate_bps_ = rate_bps; }
    double rate_bps() const { return rate_bps_; }

    /// Time to put `bits` on the wire at the current rate; Duration::max() when the rate is 0.
    base::Duration transmit_time(std::uint64_t bits) const;

    /// True if a sample may be handed to the link now.
    bool can_send(base::SteadyTime now) const { return rate_bps_ > 0.0 && busy_until_ <= now + lead_; }

    /// When the link will have drained what was charged.
    base::SteadyTime busy_until() const { return busy_until_; }

    /// When the next sample may be handed to the link.
    base::SteadyTime next_send_time() const { return busy_until_ - lead_; }

    /// The link is seen busy until at least `t` (a queue the budget did not fill itself).
    void hold_until(base::SteadyTime t) { busy_until_ = std::max(busy_until_, t); }

    /// What was charged beyond `t` never reaches the link (a queue dropped it): free from `t` on.
    void release_to(base::SteadyTime t) { busy_until_ = std::min(busy_until_, t); }

    /// Give back `bits` charged before that did not go to the link then (they will be charged when they do).
    void refund(std::uint64_t bits) { busy_until_ -= std::min(transmit_time(bits), busy_until_.time_since_epoch()); }
    /// Charge `bits` sent at `now`; returns when they will have left the link.
    base::SteadyTime charge(base::SteadyTime now, std::uint64_t bits);

  private:
    double rate_bps_;
    base::Duration lead_;
    base::SteadyTime busy_until_{};
};

}  // namespace tgw::core
