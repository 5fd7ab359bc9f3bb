#pragma once

#include <cstdint>
#include <vector>

#include "core/paper_workload.hpp"
#include "core/scheduler.hpp"
#include "gateway/sim/delivery_stats.hpp"
#include "gateway/sim/rate_profile.hpp"

namespace tgw::sim {

struct SimulationConfig {
    core::SchedulerConfig scheduler;  ///< policy, wire model, memory cap; the initial rate comes from `link`
    std::vector<core::MessageStream> workload = core::paper_workload();
    RateProfile link = RateProfile::constant(20'000);
    base::Duration duration = std::chrono::seconds(60);
    /// Publishing before the measured window starts, so that queues are in their steady state (0: the
    /// paper's fresh start).
    base::Duration warmup = base::Duration::zero();
    /// The shaper's queue depth (tbf `latency`): it holds link rate/8 * this + `link_burst_bytes` bytes.
    base::Duration link_queue_limit = std::chrono::seconds(1);
    /// The shaper's token bucket (tbf `burst`), as scripts/testbed sets it.
    std::uint64_t link_burst_bytes = 1600;
    /// The link as the gateway believes it: the wire model's cost times this (1.0 = perfectly calibrated).
    double true_overhead_factor = 1.0;
};

struct SimulationResult {
    std::vector<DeliveryStats> per_stream;  ///< in workload order
    core::TopicCounters gateway_counters;
    std::uint64_t link_sent_bits = 0;
    std::uint64_t link_dropped_bits = 0;
    /// What the link could carry over the measured window: the bar the on-time payload is held against.
    double measured_capacity_bits = 0.0;
};

/// The scheduler alone in simulated time: the workload's streams publish periodically (phases spread within
/// a period), the scheduler releases into a SimulatedLink, and each sample's fate is recorded. The sensor
/// is perfect: the scheduler is told each rate step as it happens. The samples published during `duration`,
/// after `warmup`, are measured; publishing goes on for the longest TTL after it, so that the measured samples still
/// queued at the end meet the same competition as the others (steady state, no end-of-run burst).
SimulationResult run_simulation(const SimulationConfig& config);

}  // namespace tgw::sim
