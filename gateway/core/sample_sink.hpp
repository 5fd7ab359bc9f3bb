#pragma once

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
    /// The sample will not be sent: keep it, with the reason.
    virtual void drop(Sample&& sample, DropReason reason) = 0;
};

}  // namespace tgw::core
