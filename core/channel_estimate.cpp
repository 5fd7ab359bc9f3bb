#include "core/channel_estimate.hpp"

#include <algorithm>
#include <cmath>

#include "base/config_error.hpp"

namespace tgw::core {

std::string ChannelEstimateConfig::validate() const {
    if (!(decrease_factor > 0 && decrease_factor < 1))
        return "decrease_factor must be in (0, 1)";
    if (!(increase_fraction_per_s >= 0 && std::isfinite(increase_fraction_per_s)))
        return "increase_fraction_per_s must be a fraction >= 0";
    if (max_queueing <= base::Duration::zero())
        return "max_queueing must be above 0";
    if (decrease_interval < base::Duration::zero())
        return "decrease_interval must not be negative";
    if (!(start_fraction > 0 && start_fraction <= 1))
        return "start_fraction must be in (0, 1]";
    if (!(start_growth_per_s >= 0 && std::isfinite(start_growth_per_s)))
        return "start_growth_per_s must be a fraction >= 0";
    if (!(min_fraction > 0 && min_fraction <= 1))
        return "min_fraction must be in (0, 1]";
    if (!(min_utilisation >= 0 && min_utilisation <= 1))
        return "min_utilisation must be in [0, 1]";
    if (hold_queueing <= base::Duration::zero() || hold_queueing > max_queueing)
        return "hold_queueing must be above 0 and at most max_queueing";
    if (interval <= base::Duration::zero())
        return "interval must be above 0";
    if (delivered_window < interval)
        return "delivered_window must be at least interval";
    if (baseline_window <= base::Duration::zero())
        return "baseline_window must be above 0";
    if (joining < base::Duration::zero())
        return "joining must not be negative";
    return "";
}

const char* to_string(ChannelVerdict verdict) {
    switch (verdict) {
        case ChannelVerdict::unknown:
            return "unknown";
        case ChannelVerdict::clear:
            return "clear";
        case ChannelVerdict::full:
            return "full";
        case ChannelVerdict::draining:
            return "draining";
        case ChannelVerdict::queueing:
            return "queueing";
        case ChannelVerdict::losing:
            return "losing";
    }
    return "unknown";
}

base::Duration ChannelEstimate::Baseline::least() const {
    return *std::min_element(minimum, minimum + steps);
}

ChannelEstimate::ChannelEstimate(double upper_bps, ChannelEstimateConfig config, const base::Clock& clock)
    : config_(config), clock_(clock), upper_bps_(upper_bps) {
    if (const std::string error = config_.validate(); !error.empty())
        throw base::ConfigError("channel estimate: " + error);
    if (!(upper_bps > 0 && std::isfinite(upper_bps)))
        throw base::ConfigError("channel estimate: the upper bound must be a rate above 0");
    estimate_bps_ = std::max(config_.min_fraction, config_.start_fraction) * upper_bps_;
    starting_ = estimate_bps_ < upper_bps_;
}

void ChannelEstimate::arrived(const std::string& sender, base::Duration one_way, std::size_t wire_bytes) {
    // Its own time on the wire is not queueing: a 3 kB bundle takes 400 ms at 60 kbit/s. Taken at the bound, which
    // it never took less than: at an estimate below the channel's rate a large datagram looked quicker than any
    // before it, and every small one after it queued (a relay measuring a 30,000 bit/s channel held it at 16,000,
    // "full" every other second, hazards 153 of 300 on time). Too little taken off only makes a large datagram
    // look later, and the interval's queue is its quickest datagram's.
    const base::Duration adjusted = one_way - base::from_seconds(8.0 * static_cast<double>(wire_bytes) / upper_bps_);
    const base::SteadyTime now = clock_.now();
    Baseline& baseline = baselines_[sender];
    if (baseline.steps == 0) {
        baseline.joined = now;
        baseline.step_start = now;
        baseline.minimum[0] = adjusted;
        baseline.steps = 1;
    } else if (now - baseline.step_start >= config_.baseline_window / Baseline::STEPS) {
        std::copy_backward(baseline.minimum, baseline.minimum + Baseline::STEPS - 1,
                           baseline.minimum + Baseline::STEPS);
        baseline.minimum[0] = adjusted;
        baseline.steps = std::min(baseline.steps + 1, Baseline::STEPS);
        baseline.step_start = now;
    } else {
        baseline.minimum[0] = std::min(baseline.minimum[0], adjusted);
    }
    const base::Duration queued = std::max(base::Duration::zero(), adjusted - baseline.least());
    // The least of the interval: a queue that stands delays every sample, a burst of one sender's only some.
    const bool joining = baseline.joining(now, config_.joining);
    std::optional<base::Duration>& least = joining ? joining_queueing_ : interval_queueing_;
    least = least ? std::min(*least, queued) : queued;
    if (joining)
        baseline.interval_quickest =
            baseline.interval_quickest ? std::min(*baseline.interval_quickest, adjusted) : adjusted;
}

std::optional<base::Duration> ChannelEstimate::end_interval(base::SteadyTime now) {
    const std::optional<base::Duration> known = interval_queueing_;
    for (auto& [sender, baseline] : baselines_) {
        // A sender that joined a queue waited in it as long as the others: its quickest without it. Only while it
        // still joins: one whose own delays told the queue would correct itself by it.
        if (known && baseline.interval_quickest && baseline.joining(now, config_.joining))
            baseline.minimum[0] = std::min(baseline.minimum[0], *baseline.interval_quickest - *known);
        baseline.interval_quickest.reset();
    }
    const std::optional<base::Duration> queueing = known ? known : joining_queueing_;  // a fleet that starts at once
    interval_queueing_.reset();
    joining_queueing_.reset();
    return queueing;
}

double ChannelEstimate::update(std::uint64_t delivered_wire_bytes, std::uint64_t lost_samples, double granted_bps) {
    const base::SteadyTime now = clock_.now();
    const Counters counters{now, delivered_wire_bytes, lost_samples};
    if (!last_ || delivered_wire_bytes < last_->delivered_wire_bytes || lost_samples < last_->lost_samples) {
        last_ = counters;  // the first, or the counters started again: measure from here
        window_.assign(1, counters);
        end_interval(now);
        return estimate_bps_;
    }
    const base::Duration elapsed = now - last_->at;
    if (elapsed < config_.interval)
        return estimate_bps_;
    const bool lost = lost_samples > last_->lost_samples;
    window_.push_back(counters);
    while (window_.size() > 2 && now - window_[1].at >= config_.delivered_window)
        window_.pop_front();
    const double delivered = 8.0 * static_cast<double>(delivered_wire_bytes - window_.front().delivered_wire_bytes) /
                             base::to_seconds(now - window_.front().at);
    // The slow start judges its growth by the last interval alone: the window's rate lags an estimate growing by a
    // tenth a second, and held it back while every robot used all of it (with min_utilisation at 0.85, three
    // robots' A 196.5 of 200 on time on average over 6 runs, against 198.7 over 7 judged by the interval).
    const double delivered_lately =
        8.0 * static_cast<double>(delivered_wire_bytes - last_->delivered_wire_bytes) / base::to_seconds(elapsed);
    const std::optional<base::Duration> previous_queueing = queueing_;
    delivered_bps_ = delivered;
    recent_delivered_.emplace_back(now, delivered);
    while (now - recent_delivered_.front().first > config_.joining)
        recent_delivered_.pop_front();
    queueing_ = end_interval(now);
    last_ = counters;

    const bool queue = queueing_ && *queueing_ > config_.max_queueing;
    if (starting_ && (lost || (queueing_ && *queueing_ > config_.hold_queueing))) {
        // The first queue: the channel is full, and what it carried is the best guess of it, above the estimate
        // (robots not yet granted send at a newcomer's share of their own sensor's rate) or below it (the grants
        // outran the channel while the delivered rate lagged them: its window, and the grants' way to the robots).
        starting_ = false;
        estimate_bps_ = std::clamp(delivered, config_.min_fraction * upper_bps_, upper_bps_);
    }
    const bool shrinking = queue && previous_queueing && *queueing_ < *previous_queueing;
    if (lost || (queue && !shrinking)) {
        verdict_ = lost ? ChannelVerdict::losing : ChannelVerdict::queueing;
        // Behind a queue, what arrived in its own second, where more: the channel carried all it could then, and no
        // more (the camp hears it past the bottleneck). Over the window alone, a queue that a robot's return made
        // after seconds of less traffic cut a channel of 60,000 bit/s to 29,682, and the others' hazards expired as
        // their grants halved. A loss alone does not say the channel was full.
        cut(queue ? std::max(delivered, delivered_lately) : delivered, now, joined_lately(now));
    } else if (queue) {
        verdict_ = ChannelVerdict::draining;  // the last cut shows: wait for the queue to go
    } else if (queueing_ && *queueing_ > config_.hold_queueing) {
        // Full: ease down, the more the longer the queue, so that the estimate settles where a short queue stands
        // instead of growing into a long one and being cut.
        verdict_ = ChannelVerdict::full;
        const double over = base::to_seconds(*queueing_ - config_.hold_queueing) /
                            base::to_seconds(config_.max_queueing - config_.hold_queueing);
        estimate_bps_ =
            std::max(config_.min_fraction * upper_bps_,
                     estimate_bps_ - over * config_.increase_fraction_per_s * upper_bps_ * base::to_seconds(elapsed));
    } else {
        verdict_ = ChannelVerdict::clear;
        if (queueing_ && granted_bps > 0) {  // nothing granted: no robot to prove the channel
            estimate_bps_ = grown(elapsed, starting_ ? delivered_lately : delivered, *queueing_);
            starting_ = starting_ && estimate_bps_ < upper_bps_;
        }
    }
    return estimate_bps_;
}

double ChannelEstimate::grown(base::Duration elapsed, double delivered_bps, base::Duration queueing) const {
    // Only on evidence: samples that crossed while the robots used the estimate.
    if (delivered_bps < config_.min_utilisation * estimate_bps_)
        return estimate_bps_;
    const double seconds = base::to_seconds(elapsed);
    if (starting_)
        return std::min(upper_bps_, estimate_bps_ * std::pow(1.0 + config_.start_growth_per_s, seconds));
    // The slower the nearer the queue is to full.
    const double room = 1.0 - base::to_seconds(queueing) / base::to_seconds(config_.hold_queueing);
    return std::min(upper_bps_, estimate_bps_ + room * config_.increase_fraction_per_s * upper_bps_ * seconds);
}

bool ChannelEstimate::joined_lately(base::SteadyTime now) const {
    bool joining = participant_joined_ && now - *participant_joined_ < config_.joining;
    bool known = false;
    for (const auto& [sender, baseline] : baselines_) {
        (baseline.joining(now, config_.joining) ? joining : known) = true;
    }
    return joining && known;
}

void ChannelEstimate::cut(double delivered_bps, base::SteadyTime now, bool burst) {
    if (last_cut_ && now - *last_cut_ < config_.decrease_interval)
        return;
    // What the channel carried while it queued is about what it can carry: below it, the queue drains. Cut after
    // cut while a queue lasts (one that traffic outside the grants keeps up), a twentieth of the estimate each:
    // compounding the whole factor took a channel of 30,000 bit/s to 24,000 in two cuts at a fleet's start.
    // A sender that joins a running fleet announces itself in a burst of discovery the camp does not all see
    // (with a discovery server, none of it: the server takes it), and the channel looks half used while it
    // queues: cut to the most it delivered lately instead (by the twentieth at least). Its samples are in the
    // grants already (the newcomers' share), and the burst drains by itself. Cut to what was delivered, a
    // restarted gateway's discovery took a channel of 61,950 bit/s to 44,923, and the others' hazards expired on
    // their halved grants; cut by the twentieth alone, an estimate of 70,781 on that channel of 60,000 came down
    // by 5 % every 2 s while a queue of 500 ms stood.
    double to = std::min(config_.decrease_factor * delivered_bps, 0.95 * estimate_bps_);
    if (burst) {
        double peak = 0;
        for (const auto& [at, bps] : recent_delivered_)
            peak = std::max(peak, bps);
        to = std::min(0.95 * estimate_bps_, std::max(to, peak));
    }
    estimate_bps_ = std::max(config_.min_fraction * upper_bps_, to);
    last_cut_ = now;
}

}  // namespace tgw::core
