#include "gateway/dds/gateway_sink.hpp"

#include <utility>

namespace tgw::dds {

GatewaySink::GatewaySink(WanRouter& wan, log::RobotLog* log, const TopicDirectory& topics, const core::Clock& clock)
    : wan_(wan), log_(log), topics_(topics), clock_(clock) {}

bool GatewaySink::forward(core::Sample&& sample) {
    if (wan_.write(sample) != WriteResult::ok) {
        // The payload is still ours: keep it, so that a refused write is never silently lost.
        wan_write_failures_.fetch_add(1, std::memory_order_relaxed);
        drop(std::move(sample), core::DropReason::write_failed);
        return false;
    }
    processing_latency_.record(clock_.now() - sample.arrival);
    return true;
}

void GatewaySink::drop(core::Sample&& sample, core::DropReason reason) {
    if (log_ == nullptr) {
        return;
    }
    const TopicDirectory::Names names = topics_.get(sample.topic);
    log::LogRecord record;
    record.topic = names.topic;
    record.type_name = names.type_name;
    record.sample = &sample;
    record.reason = reason;
    record.arrival = to_wall(sample.arrival);
    record.deadline = to_wall(sample.deadline);
    record.logged_at = clock_.wall_now();
    log_->append(record);
    logged_.fetch_add(1, std::memory_order_relaxed);
}

core::WallTime GatewaySink::to_wall(core::SteadyTime t) const {
    return clock_.wall_now() + std::chrono::duration_cast<core::WallClock::duration>(t - clock_.now());
}

}  // namespace tgw::dds
