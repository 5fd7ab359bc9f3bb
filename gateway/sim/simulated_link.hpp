#pragma once

#include <cstdint>
#include <optional>

#include "gateway/core/time.hpp"
#include "gateway/sim/rate_profile.hpp"

namespace tgw::sim {

/// The shaped link of the testbed in simulated time: a tbf-like FIFO queue in front of a non-preemptive
/// link whose rate follows a RateProfile. A packet that would wait longer than the queue's latency limit is
/// dropped, as tbf drops it.
class SimulatedLink {
  public:
    SimulatedLink(RateProfile rate, core::SteadyTime start, core::Duration queue_limit);

    /// Hands `bits` to the link at `now`; returns when they arrive, or nullopt if the queue dropped them.
    std::optional<core::SteadyTime> send(core::SteadyTime now, std::uint64_t bits);

    std::uint64_t sent_bits() const { return sent_bits_; }
    std::uint64_t dropped_bits() const { return dropped_bits_; }

  private:
    RateProfile rate_;
    core::SteadyTime start_;
    core::Duration queue_limit_;
    core::SteadyTime busy_until_;
    std::uint64_t sent_bits_ = 0;
    std::uint64_t dropped_bits_ = 0;
};

}  // namespace tgw::sim
