#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "base/time.hpp"
#include "core/drop_reason.hpp"

namespace tgw::sim {

/// The paper's two metrics for one message type: how many arrived within their TTL, and the mean and
/// standard deviation of transmission time (arrival at the base camp minus generation) of those that arrived.
struct DeliveryStats {
    std::uint64_t offered = 0;
    std::uint64_t on_time = 0;
    std::uint64_t late = 0;
    std::uint64_t lost_on_link = 0;
    std::array<std::uint64_t, core::DROP_REASON_COUNT> logged{};

    void record_delivery(base::Duration transmission_time, base::Duration ttl) {
        const double s = base::to_seconds(transmission_time);
        (transmission_time <= ttl ? on_time : late) += 1;
        sum_s_ += s;
        sum_sq_s_ += s * s;
    }
    void record_log(core::DropReason reason) { ++logged[static_cast<std::size_t>(reason)]; }

    std::uint64_t delivered() const { return on_time + late; }
    double on_time_percent() const {
        return offered ? 100.0 * static_cast<double>(on_time) / static_cast<double>(offered) : 0.0;
    }
    double mean_s() const { return delivered() ? sum_s_ / static_cast<double>(delivered()) : 0.0; }
    double stddev_s() const {
        if (delivered() < 2)
            return 0.0;
        const double n = static_cast<double>(delivered());
        const double var = (sum_sq_s_ - sum_s_ * sum_s_ / n) / (n - 1.0);
        return var > 0.0 ? std::sqrt(var) : 0.0;
    }

  private:
    double sum_s_ = 0.0;
    double sum_sq_s_ = 0.0;
};

}  // namespace tgw::sim
