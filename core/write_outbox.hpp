// The scheduler's decisions, kept in order to be written after the forwarding loop's lock is released.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "core/sample_sink.hpp"

namespace tgw::core {

/// A SampleSink that only records: ForwardingLoop decides under its lock into an outbox, and writes it to the
/// real sink after releasing the lock, so that a WAN write that blocks (up to 100 ms on a full socket) holds up
/// no robot listener. forward() reports success; a write that fails later is settled with
/// Scheduler::forward_failed. A bundle is encoded at once by the real sink (encode_bundle), so that the budget
/// charges its real size, and written later (write_bundle).
class WriteOutbox final : public SampleSink {
  public:
    /// A bundle encoded under the lock, to be written after it.
    struct BundleWrite {
        std::vector<Sample> entries;  ///< encoded as `encoded`
        EncodedBundle encoded;
        /// The chunked sample whose last chunk it carries (SampleSink::chunked_sample_left).
        std::optional<Sample> completed;
    };
    struct Decision {
        enum class Kind : std::uint8_t { forward, drop, bundle, send_repair, discard_repair, sample_cut_short };
        Kind kind = Kind::drop;
        Sample sample;                             ///< forward, drop
        DropReason reason = DropReason::shutdown;  ///< drop, sample_cut_short
        std::uint64_t repair_id = 0;  ///< send_repair, discard_repair; the sample's number for sample_cut_short
        /// bundle. Apart, so that the decision standard mode makes per sample stays the size of a sample.
        std::unique_ptr<BundleWrite> bundle;
    };

    /// `encoder` encodes the bundles (the sink the decisions will be written to).
    explicit WriteOutbox(SampleSink& encoder) : encoder_(encoder) {}

    bool forward(Sample&& sample) override {
        Decision& d = push(Decision::Kind::forward);
        d.sample = std::move(sample);
        return true;
    }
    std::size_t forward_bundle(std::vector<Sample>&& samples, std::size_t wire_bytes) override {
        EncodedBundle encoded;
        const std::size_t real_bytes = encoder_.encode_bundle(samples, wire_bytes, encoded);
        if (real_bytes == 0) {
            // Not written, by the contract of forward_bundle: each sample is kept, but the chunks, whose sample
            // the scheduler logs whole.
            for (Sample& sample : samples) {
                if (!sample.chunk) {
                    drop(std::move(sample), DropReason::write_failed);
                }
            }
            return 0;
        }
        Decision& d = push(Decision::Kind::bundle);
        d.bundle = std::make_unique<BundleWrite>();
        d.bundle->entries = std::move(samples);
        d.bundle->encoded = std::move(encoded);
        return real_bytes;
    }
    void chunked_sample_left(Sample&& whole) override {
        // Called right after the bundle that carried its last chunk was recorded.
        if (!decisions_.empty() && decisions_.back().kind == Decision::Kind::bundle) {
            decisions_.back().bundle->completed = std::move(whole);
        }
    }
    void send_repair(std::uint64_t id) override { push(Decision::Kind::send_repair).repair_id = id; }
    void discard_repair(std::uint64_t id) override { push(Decision::Kind::discard_repair).repair_id = id; }
    void sample_cut_short(std::uint64_t sample, DropReason reason) override {
        Decision& d = push(Decision::Kind::sample_cut_short);
        d.repair_id = sample;
        d.reason = reason;
    }
    void drop(Sample&& sample, DropReason reason) override {
        Decision& d = push(Decision::Kind::drop);
        d.sample = std::move(sample);
        d.reason = reason;
    }

    bool empty() const { return decisions_.empty(); }
    /// Moves everything recorded so far, in order, into `out` (cleared first); the outbox is empty after and
    /// keeps `out`'s storage, so that a steady flow allocates little.
    void take(std::vector<Decision>& out) {
        out.clear();
        std::swap(out, decisions_);
    }

  private:
    Decision& push(Decision::Kind kind) {
        Decision& d = decisions_.emplace_back();
        d.kind = kind;
        return d;
    }

    SampleSink& encoder_;
    std::vector<Decision> decisions_;
};

}  // namespace tgw::core
