#include "core/paper_filter.hpp"

namespace tgw::core {

std::optional<std::vector<DeadlineQueue::Slot>> PaperFilter::run(base::SteadyTime now, DeadlineQueue& queue,
                                                                 double rate_bps) {
    if (!started_) {
        next_ = now;
        started_ = true;
    }
    if (now < next_) {
        return std::nullopt;
    }
    double remaining_bits = rate_bps * base::to_seconds(period_);
    std::vector<DeadlineQueue::Slot> marked;
    queue.visit_by_urgency([&](DeadlineQueue::Slot slot) {
        const double bits = 8.0 * static_cast<double>(queue.at(slot).payload_bytes) * (1.0 + overhead_);
        if (bits <= remaining_bits) {
            remaining_bits -= bits;
            marked.push_back(slot);
        }
        return true;
    });
    next_ += period_;
    if (next_ <= now) {
        next_ = now + period_;  // a release that came late starts the periods anew
    }
    return marked;
}

}  // namespace tgw::core
