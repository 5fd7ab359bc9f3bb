#pragma once

#include <cstdint>
#include <deque>
#include <optional>

#include "base/time.hpp"
#include "gateway/sim/rate_profile.hpp"

namespace tgw::sim {

/// The testbed's shaper in simulated time: Linux tbf (`rate R burst B latency L`) on a veth, whose own
/// transmission takes no time. A token bucket of `burst_bytes` fills at the current rate of a RateProfile; the
/// packet at the head of a FIFO leaves as soon as the bucket holds its size. The FIFO holds at most
/// R/8 * L + B bytes, the limit tc computes from the rate in force (a rate change recomputes it, as `tc qdisc
/// change` does, and keeps what is queued); a packet that does not fit on arrival is dropped. A rate change
/// also refills the bucket, as tbf does when its parameters change.
class SimulatedLink {
  public:
    /// `latency` is tbf's `latency` (the queue depth at the current rate), `burst_bytes` its bucket.
    SimulatedLink(RateProfile rate, base::SteadyTime start, base::Duration latency, std::uint64_t burst_bytes);

    /// Hands `bits` to the shaper at `now` (calls in non-decreasing `now`); returns when they leave it, which
    /// is when they arrive, or nullopt if the queue dropped them or the rate never lets them leave.
    std::optional<base::SteadyTime> send(base::SteadyTime now, std::uint64_t bits);

    /// The queue's limit in bytes at `now`: rate/8 * latency + burst, rounded down as tc does.
    std::uint64_t queue_limit_bytes(base::SteadyTime now) const;

    std::uint64_t sent_bits() const { return sent_bits_; }
    std::uint64_t dropped_bits() const { return dropped_bits_; }

  private:
    struct Queued {
        base::SteadyTime departs;
        std::uint64_t bits;
    };

    /// When a packet of `bits` at the head of the queue from `head_at` leaves; updates the bucket.
    std::optional<base::SteadyTime> departure(base::SteadyTime head_at, std::uint64_t bits);

    RateProfile rate_;
    base::SteadyTime start_;
    base::Duration latency_;
    double burst_bits_;
    /// The bucket's tokens right after the last departure (negative after a packet larger than the bucket).
    double tokens_bits_;
    base::SteadyTime last_departure_;
    /// Packets not yet gone at the last send, in departure order, and their total.
    std::deque<Queued> queue_;
    std::uint64_t backlog_bits_ = 0;
    std::uint64_t sent_bits_ = 0;
    std::uint64_t dropped_bits_ = 0;
};

}  // namespace tgw::sim
