// The scheduler's decisions, kept in order to be written after the forwarding loop's lock is released.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "gateway/core/sample_sink.hpp"

namespace tgw::core {

/// A SampleSink that only records: ForwardingLoop decides under its lock into an outbox, and writes it to the
/// real sink after releasing the lock, so that a WAN write that blocks (up to 100 ms on a full socket) holds up
/// no robot listener. forward() reports success; a write that fails later is settled with
/// Scheduler::forward_failed. Standard WAN mode only: a bundle's real size feeds the budget at once, so compact
/// mode writes under the lock; should forward_bundle be called here anyway, its samples are kept as
/// DropReason::write_failed (the contract of a bundle not written), never lost.
class WriteOutbox final : public SampleSink {
  public:
    struct Decision {
        Sample sample;
        bool forward = false;  ///< forward it; else drop it with `reason`
        DropReason reason = DropReason::shutdown;
    };

    bool forward(Sample&& sample) override {
        decisions_.push_back(Decision{std::move(sample), true, DropReason::shutdown});
        return true;
    }
    std::size_t forward_bundle(std::vector<Sample>&& samples, std::size_t /*wire_bytes*/) override {
        for (Sample& sample : samples) {
            if (!sample.chunk) {  // the scheduler keeps a chunked sample whole and logs it then
                decisions_.push_back(Decision{std::move(sample), false, DropReason::write_failed});
            }
        }
        return 0;
    }
    void drop(Sample&& sample, DropReason reason) override {
        decisions_.push_back(Decision{std::move(sample), false, reason});
    }

    bool empty() const { return decisions_.empty(); }
    /// Moves everything recorded so far, in order, into `out` (cleared first); the outbox is empty after and
    /// keeps `out`'s storage, so that a steady flow allocates nothing.
    void take(std::vector<Decision>& out) {
        out.clear();
        std::swap(out, decisions_);
    }

  private:
    std::vector<Decision> decisions_;
};

}  // namespace tgw::core
