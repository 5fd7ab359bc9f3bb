#include "sensor/delivered_rate_estimator.hpp"

#include <algorithm>
#include <cmath>

#include "base/config_error.hpp"

namespace tgw::sensor {

namespace {

constexpr double BITS_PER_BYTE = 8.0;

bool any_went_back(const LinkCounters& now, const LinkCounters& before) {
    return now.gateway_sent_bytes < before.gateway_sent_bytes || now.tx_bytes < before.tx_bytes ||
           now.drops < before.drops;
}

}  // namespace

std::string DeliveredRateConfig::validate() const {
    if (!(decrease_factor > 0.0 && decrease_factor < 1.0))
        return "decrease_factor must be in (0, 1)";
    if (!(increase_fraction_per_s > 0.0 && std::isfinite(increase_fraction_per_s)))
        return "increase_fraction_per_s must be above 0";
    if (max_queue_delay <= base::Duration::zero())
        return "max_queue_delay must be above 0";
    if (decrease_interval < base::Duration::zero())
        return "decrease_interval must not be negative";
    if (!(min_cap_fraction > 0.0 && min_cap_fraction <= 1.0))
        return "min_cap_fraction must be in (0, 1]";
    if (!(min_utilisation >= 0.0 && min_utilisation <= 1.0))
        return "min_utilisation must be in [0, 1]";
    if (delivered_window <= base::Duration::zero())
        return "delivered_window must be above 0";
    return {};
}

DeliveredRateEstimator::DeliveredRateEstimator(DeliveredRateConfig config, const base::Clock& clock)
    : config_(config), clock_(clock) {
    if (auto error = config_.validate(); !error.empty())
        throw base::ConfigError("delivered-rate check: " + error);
}

double DeliveredRateEstimator::budget(double claimed_bps) const {
    return cap_bps_ ? std::min(*cap_bps_, claimed_bps) : claimed_bps;
}

double DeliveredRateEstimator::update(const LinkCounters& counters, double claimed_bps) {
    const base::SteadyTime now = clock_.now();
    if (!std::isfinite(claimed_bps) || claimed_bps < 0.0)
        return 0.0;
    if (!previous_ || any_went_back(counters, previous_->counters) || now <= previous_->at) {
        // A first sample, or counters that reset: only a baseline to measure the next interval from.
        if (!previous_ || now > previous_->at) {
            previous_ = Sample{now, counters};
            window_start_ = previous_;
        }
        return budget(claimed_bps);
    }
    const Sample before = *previous_;
    previous_ = Sample{now, counters};
    const double interval_s = base::to_seconds(now - before.at);
    const double sent_bps = BITS_PER_BYTE *
                            static_cast<double>(counters.gateway_sent_bytes - before.counters.gateway_sent_bytes) /
                            interval_s;
    if (now - window_start_->at >= config_.delivered_window) {
        delivered_bps_ = BITS_PER_BYTE * static_cast<double>(counters.tx_bytes - window_start_->counters.tx_bytes) /
                         base::to_seconds(now - window_start_->at);
        window_start_ = previous_;
    }

    const double effective_bps = budget(claimed_bps);
    const double drain_bytes = effective_bps / BITS_PER_BYTE * base::to_seconds(config_.max_queue_delay);
    const double backlog_limit = std::max(drain_bytes, static_cast<double>(config_.min_backlog_bytes));
    const bool dropped = counters.drops > before.counters.drops;
    const bool long_queue = static_cast<double>(counters.backlog_bytes) > backlog_limit;
    const bool growing = counters.backlog_bytes >= before.counters.backlog_bytes;

    if (dropped || (long_queue && growing)) {
        verdict_ = LinkVerdict::congested;
        if (!last_decrease_ || now - *last_decrease_ >= config_.decrease_interval) {
            const double carried_bps = config_.decrease_factor * delivered_bps_.value_or(0.0);
            cap_bps_ = std::min(effective_bps, std::max({config_.decrease_factor * effective_bps, carried_bps,
                                                         config_.min_cap_fraction * claimed_bps}));
            last_decrease_ = now;
        }
    } else if (long_queue) {
        verdict_ = LinkVerdict::draining;
    } else {
        verdict_ = LinkVerdict::delivering;
        if (cap_bps_ && sent_bps >= config_.min_utilisation * effective_bps)
            *cap_bps_ += config_.increase_fraction_per_s * claimed_bps * interval_s;
        if (cap_bps_ && *cap_bps_ >= claimed_bps)
            cap_bps_.reset();
    }
    return budget(claimed_bps);
}

}  // namespace tgw::sensor
