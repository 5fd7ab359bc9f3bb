#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/drop_reason.hpp"
#include "core/sample.hpp"

namespace tgw::core {

/// Compact WAN mode: a bundle encoded when the scheduler decided it, to be written after the forwarding loop's
/// lock is released (SampleSink::encode_bundle, SampleSink::write_bundle).
struct EncodedBundle {
    std::vector<std::uint8_t> bytes;  ///< what the sink writes; its own format
    std::size_t wire_bytes = 0;       ///< what it takes on the link, as the budget charged it
};

/// Where the scheduler's decisions go: the WAN router for samples it releases, the on-robot log for the rest.
/// Implementations must not throw; a failed write is counted and logged by the implementation.
class SampleSink {
  public:
    virtual ~SampleSink() = default;
    /// The budget admitted the sample: write it to the WAN now. False when it could not be written: the sink
    /// has then kept it as DropReason::write_failed itself, and it does not count as forwarded.
    virtual bool forward(Sample&& sample) = 0;
    /// Compact WAN mode: the budget admitted `samples` to leave together, in this order, as one bundle of at
    /// most `wire_bytes` on the link. Returns what it really put there (compression may make it less), which the
    /// budget charges; 0 when it could not be written: the sink has then kept every one of the samples as
    /// DropReason::write_failed itself, all but the chunks (Sample::chunk): the scheduler keeps a chunked sample
    /// whole and logs it then. A chunked sample has left once its last chunk (Sample::completes_sample) has.
    virtual std::size_t forward_bundle(std::vector<Sample>&& samples, std::size_t wire_bytes) = 0;
    /// The sample will not be sent: keep it, with the reason.
    virtual void drop(Sample&& sample, DropReason reason) = 0;

    /// forward_bundle in two halves, for a caller that decides under a lock and writes after it (ForwardingLoop).
    /// The first encodes `samples` (left as they were) into `out` and returns its wire bytes (what the budget charges),
    /// or 0 when it cannot: the samples are then the caller's to keep. It must be fast (no I/O): it runs under the
    /// lock. The default encodes nothing and takes the scheduler's bound `wire_bytes` as the size.
    virtual std::size_t encode_bundle(std::vector<Sample>& /*samples*/, std::size_t wire_bytes, EncodedBundle& out) {
        out.bytes.clear();
        out.wire_bytes = wire_bytes;
        return wire_bytes;
    }
    /// The second half: writes what encode_bundle made of `samples`, in the order the bundles were encoded. False
    /// when it could not: the sink has then kept each sample as in forward_bundle (all but the chunks).
    virtual bool write_bundle(std::vector<Sample>&& samples, EncodedBundle&& bundle) {
        return forward_bundle(std::move(samples), bundle.wire_bytes) > 0;
    }
    /// A chunked sample's last chunk went in the bundle just forwarded: here is the sample whole. A sink that
    /// writes later keeps it until that bundle is written, to log it whole should any of its chunks fail.
    virtual void chunked_sample_left(Sample&& /*whole*/) {}
    /// The budget admitted the repair of this id (Scheduler::push_repair): send its bytes now.
    virtual void send_repair(std::uint64_t /*id*/) {}
    /// The repair of this id will not be sent: forget its bytes.
    virtual void discard_repair(std::uint64_t /*id*/) {}
    /// A continuation of the sample numbered `sample` (Repair::sample) will not be sent: the sample, written, cannot
    /// arrive. It counts as dropped for `reason`: keep it, as drop() would. Once per sample, after its discard_repair.
    virtual void sample_cut_short(std::uint64_t /*sample*/, DropReason /*reason*/) {}
};

}  // namespace tgw::core
