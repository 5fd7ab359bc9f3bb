#include "gateway/sim/simulated_link.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace tgw::sim {

using base::Duration;
using base::SteadyTime;

SimulatedLink::SimulatedLink(RateProfile rate, SteadyTime start, Duration latency, std::uint64_t burst_bytes)
    : rate_(std::move(rate)),
      start_(start),
      latency_(latency),
      burst_bits_(8.0 * static_cast<double>(burst_bytes)),
      tokens_bits_(burst_bits_),
      last_departure_(start) {}

std::uint64_t SimulatedLink::queue_limit_bytes(SteadyTime now) const {
    const double rate_bps = rate_.rate_at(now - start_);
    return static_cast<std::uint64_t>(std::floor(rate_bps / 8.0 * base::to_seconds(latency_))) +
           static_cast<std::uint64_t>(burst_bits_ / 8.0);
}

std::optional<SteadyTime> SimulatedLink::send(SteadyTime now, std::uint64_t bits) {
    while (!queue_.empty() && queue_.front().departs <= now) {
        backlog_bits_ -= queue_.front().bits;
        queue_.pop_front();
    }
    if (backlog_bits_ + bits > 8 * queue_limit_bytes(now)) {
        dropped_bits_ += bits;
        return std::nullopt;
    }
    // FIFO: the packet reaches the head when the one before it has left, or at once on an empty queue.
    const auto departs = departure(std::max(now, last_departure_), bits);
    if (!departs) {
        dropped_bits_ += bits;
        return std::nullopt;
    }
    queue_.push_back({*departs, bits});
    backlog_bits_ += bits;
    sent_bits_ += bits;
    return departs;
}

std::optional<SteadyTime> SimulatedLink::departure(SteadyTime head_at, std::uint64_t bits) {
    // A packet larger than the bucket waits for a full bucket and leaves it in debt (tbf would refuse it; a
    // sample here may stand for several frames, each of which fits).
    const double needed = std::min(static_cast<double>(bits), burst_bits_);
    // Between two rate changes the rate is constant, and every change refills the bucket: the tokens at any
    // moment depend on one rate only, that since the later of the last departure and the last change.
    const Duration since_departure = last_departure_ - start_;
    const Duration head = head_at - start_;
    double tokens = tokens_bits_;
    if (rate_.next_change_after(since_departure) <= head) {
        tokens = burst_bits_;
    } else {
        tokens = std::min(burst_bits_, tokens + rate_.rate_at(head) * base::to_seconds(head - since_departure));
    }
    SteadyTime departs = head_at;
    if (tokens < needed) {
        const double rate_bps = rate_.rate_at(head);
        const Duration change = rate_.next_change_after(head);
        const Duration filled =
            rate_bps > 0.0 ? head + base::from_seconds((needed - tokens) / rate_bps) : Duration::max();
        if (change <= filled) {
            if (change == Duration::max())
                return std::nullopt;  // a rate of 0 that never ends
            departs = start_ + change;
            tokens = burst_bits_;
        } else {
            departs = start_ + filled;
            tokens = needed;
        }
    }
    tokens_bits_ = tokens - static_cast<double>(bits);
    last_departure_ = departs;
    return departs;
}

}  // namespace tgw::sim
