#pragma once

#include <optional>

#include "base/time.hpp"
#include "core/sample.hpp"

namespace tgw::core {

/// Work for the link when no live sample wants it: backfill (docs/design/backfill.md). The scheduler asks only
/// when nothing is queued, no repair waits and the link is free now, and takes one sample at a time, so what it
/// hands out never waits in the queue ahead of a live sample, and a live sample that comes meanwhile waits at most
/// the one on the wire: no longer than the non-preemptive rule allows any sample of its topic's urgency.
class IdleSource {
  public:
    virtual ~IdleSource() = default;
    /// The next sample to send, or nullopt. Called under the forwarding loop's lock: no I/O, no blocking.
    virtual std::optional<Sample> next_when_idle(base::SteadyTime now) = 0;
    /// When next_when_idle may next have one (now, or earlier, if it has one now); nullopt: not until the source
    /// wakes the loop itself (ForwardingLoop::kick).
    virtual std::optional<base::SteadyTime> next_ready(base::SteadyTime now) const = 0;
};

}  // namespace tgw::core
