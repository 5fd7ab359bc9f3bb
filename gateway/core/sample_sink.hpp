#pragma once

#include <cstddef>
#include <vector>

#include "gateway/core/drop_reason.hpp"
#include "gateway/core/sample.hpp"

namespace tgw::core {

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
};

}  // namespace tgw::core
