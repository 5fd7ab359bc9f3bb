// A topic's max_rate_hz rule: which of its samples the scheduler takes in.
#pragma once

#include "base/time.hpp"

namespace tgw::core {

/// At most `max_rate_hz` samples a second, on average and never in bursts: a token bucket of one sample that may
/// be taken a tenth of a sample early. A publisher at the cap passes whole though its samples come up to a tenth
/// of a period early or late; a faster one is thinned to the cap; a pause saves up no burst.
class RateCap {
  public:
    /// `max_rate_hz` > 0.
    explicit RateCap(double max_rate_hz);

    /// Whether a sample arriving at `now` is taken; takes its token if so.
    bool admit(base::SteadyTime now);

    /// The part of a period a sample may come early and still be taken.
    static constexpr double EARLY_FRACTION = 0.1;

  private:
    double rate_per_ns_;
    double tokens_ = 1.0;
    base::SteadyTime last_{};
    bool started_ = false;
};

}  // namespace tgw::core
