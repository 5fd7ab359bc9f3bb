// The paper's policy: the 2001 Telemetry Manager's filter, run once a period.
#pragma once

#include <optional>
#include <vector>

#include "base/time.hpp"
#include "core/deadline_queue.hpp"

namespace tgw::core {

/// Once a period it walks the queue by TTL and marks what fits in the sensed rate times the period, counting only
/// payload plus an assumed overhead (0.25 = 25 %); the marked go at once, the rest waits for the next period. The
/// paper spends the whole sensed rate: its only margin is the assumed overhead. docs/design.md §4 (`paper`).
class PaperFilter {
  public:
    PaperFilter(base::Duration period, double overhead) : period_(period), overhead_(overhead) {}

    /// The samples the period that starts at `now` sends, most urgent first; nullopt while the period runs. The
    /// first call starts the first period.
    std::optional<std::vector<DeadlineQueue::Slot>> run(base::SteadyTime now, DeadlineQueue& queue, double rate_bps);
    /// When the next period starts: `now` before the first.
    base::SteadyTime next_period(base::SteadyTime now) const { return started_ ? next_ : now; }

  private:
    base::Duration period_;
    double overhead_;
    base::SteadyTime next_{};
    bool started_ = false;
};

}  // namespace tgw::core
