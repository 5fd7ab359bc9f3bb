#pragma once

#include <cmath>

#include "base/time.hpp"

namespace tgw::core {

/// A rate measured over a sliding exponential window: what was added recently counts fully, what was added a
/// `window` ago counts e^-1 as much. The scheduler uses it for what each topic has spent of the link lately.
class DecayingRate {
  public:
    DecayingRate() : DecayingRate(std::chrono::seconds(4)) {}
    explicit DecayingRate(base::Duration window) : window_s_(base::to_seconds(window)) {}

    void add(base::SteadyTime now, double amount) {
        sum_ = decayed(now) + amount;
        at_ = now;
    }

    /// The rate per second at `now`; 0 before anything was added.
    double per_second(base::SteadyTime now) const { return decayed(now) / window_s_; }

  private:
    double decayed(base::SteadyTime now) const {
        if (sum_ == 0.0 || now <= at_) {
            return sum_;
        }
        return sum_ * std::exp(-base::to_seconds(now - at_) / window_s_);
    }

    double window_s_;
    double sum_ = 0.0;
    base::SteadyTime at_{};
};

}  // namespace tgw::core
