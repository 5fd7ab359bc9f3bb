#include "gateway/sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "gateway/sim/simulated_link.hpp"

namespace tgw::sim {

using base::Duration;
using base::SteadyTime;

namespace {

/// Records where each forwarded or logged sample ends up.
class SimulationSink final : public core::SampleSink {
  public:
    SimulationSink(const SimulationConfig& config, SimulatedLink& link, std::vector<DeliveryStats>& stats,
                   const SteadyTime& now, SteadyTime start, base::WallTime wall_start)
        : config_(config), link_(link), stats_(stats), now_(now), start_(start), wall_start_(wall_start) {}

    bool forward(core::Sample&& sample) override {
        const double bits =
            config_.true_overhead_factor * static_cast<double>(config_.scheduler.wire.wire_bits(sample.payload.size()));
        record(sample, link_.send(now_, static_cast<std::uint64_t>(std::llround(bits))));
        return true;
    }
    std::size_t forward_bundle(std::vector<core::Sample>&& samples, std::size_t wire_bytes) override {
        const double bits = config_.true_overhead_factor * 8.0 * static_cast<double>(wire_bytes);
        const auto arrived = link_.send(now_, static_cast<std::uint64_t>(std::llround(bits)));
        for (const core::Sample& sample : samples) {
            if (sample.completes_sample()) {
                record(sample, arrived);  // a chunked sample has arrived with its last chunk
            }
        }
        return wire_bytes;
    }
    void drop(core::Sample&& sample, core::DropReason reason) override {
        if (measured(sample))
            stats_[sample.topic].record_log(reason);
    }

  private:
    /// The sample reached the far end at `arrived`, or was lost on the way.
    void record(const core::Sample& sample, std::optional<SteadyTime> arrived) {
        if (!measured(sample))
            return;
        DeliveryStats& stats = stats_[sample.topic];
        if (!arrived) {
            ++stats.lost_on_link;
            return;
        }
        stats.record_delivery(*arrived - generated_at(sample), config_.workload[sample.topic].ttl);
    }
    SteadyTime generated_at(const core::Sample& sample) const {
        return start_ + std::chrono::duration_cast<Duration>(sample.source_time - wall_start_);
    }
    /// Samples published after the measured window only keep the link as busy as it was.
    bool measured(const core::Sample& sample) const {
        const SteadyTime t = generated_at(sample);
        return t >= start_ + config_.warmup && t < start_ + config_.warmup + config_.duration;
    }

    const SimulationConfig& config_;
    SimulatedLink& link_;
    std::vector<DeliveryStats>& stats_;
    const SteadyTime& now_;
    SteadyTime start_;
    base::WallTime wall_start_;
};

}  // namespace

SimulationResult run_simulation(const SimulationConfig& config) {
    const SteadyTime start{std::chrono::hours(1)};
    const base::WallTime wall_start{std::chrono::hours(24 * 365 * 50)};
    const auto wall_at = [&](SteadyTime t) {
        return wall_start + std::chrono::duration_cast<base::WallClock::duration>(t - start);
    };

    core::SchedulerConfig scheduler_config = config.scheduler;
    scheduler_config.initial_rate_bps = config.link.rate_at(Duration::zero());
    core::Scheduler scheduler(scheduler_config);
    Duration longest_ttl = Duration::zero();
    std::vector<Duration> periods;
    std::vector<SteadyTime> next_generation;
    for (std::size_t i = 0; i < config.workload.size(); ++i) {
        const core::MessageStream& stream = config.workload[i];
        scheduler.add_topic({stream.topic, stream.ttl});
        longest_ttl = std::max(longest_ttl, stream.ttl);
        periods.push_back(base::from_seconds(1.0 / stream.rate_hz));
        next_generation.push_back(start +
                                  periods.back() * static_cast<long>(i) / static_cast<long>(config.workload.size()));
    }

    SimulationResult result;
    result.per_stream.resize(config.workload.size());
    SimulatedLink link(config.link, start, config.link_queue_limit, config.link_burst_bytes);
    SteadyTime now = start;
    SimulationSink sink(config, link, result.per_stream, now, start, wall_start);

    const SteadyTime measured_begin = start + config.warmup;
    const SteadyTime measured_end = measured_begin + config.duration;
    const SteadyTime end = measured_end + longest_ttl;
    while (true) {
        SteadyTime next = end;
        for (SteadyTime g : next_generation) {
            next = std::min(next, g);
        }
        if (auto wake = scheduler.next_wakeup(now))
            next = std::min(next, std::max(*wake, now));
        const Duration change = config.link.next_change_after(now - start);
        if (change != Duration::max())
            next = std::min(next, start + change);
        if (next >= end)
            break;

        now = next;
        scheduler.set_rate(config.link.rate_at(now - start));
        for (std::size_t i = 0; i < next_generation.size(); ++i) {
            if (next_generation[i] == now) {
                core::Sample sample;
                sample.topic = static_cast<core::TopicId>(i);
                sample.payload.assign(core::paper_message_serialized_bytes(config.workload[i].data_bytes), 0);
                sample.payload[1] = 1;  // the encapsulation header of little-endian plain CDR, as publishers write
                sample.source_time = wall_at(now);
                if (now >= measured_begin && now < measured_end)
                    ++result.per_stream[i].offered;
                scheduler.push(std::move(sample), now, wall_at(now), sink);
                next_generation[i] += periods[i];
            }
        }
        scheduler.release(now, sink);
    }
    now = end;
    scheduler.release(now, sink);
    scheduler.drain(sink);

    result.gateway_counters = scheduler.total_counters();
    result.link_sent_bits = link.sent_bits();
    result.link_dropped_bits = link.dropped_bits();
    result.measured_capacity_bits = config.link.capacity_bits(config.warmup, config.warmup + config.duration);
    return result;
}

}  // namespace tgw::sim
