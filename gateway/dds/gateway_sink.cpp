#include "gateway/dds/gateway_sink.hpp"

#include <utility>

namespace tgw::dds {

GatewaySink::GatewaySink(const TopicTable& topics, log::RobotLog* log, const core::Clock& clock)
    : topics_(topics), log_(log), clock_(clock) {}

void GatewaySink::set_status_route(core::TopicId id, std::shared_ptr<WanWriter> writer) {
    status_topic_ = id;
    status_writer_ = std::move(writer);
}

bool GatewaySink::forward(core::Sample&& sample) {
    WriteResult result = WriteResult::unknown_topic;
    if (sample.topic == status_topic_) {
        result = status_writer_->write(sample);
    } else if (const TopicBridge* bridge = topics_.find(sample.topic)) {
        result = bridge->write(sample);
    }
    if (result != WriteResult::ok) {
        // The payload is still ours: keep it, so that a refused write is never silently lost.
        wan_write_failures_.fetch_add(1, std::memory_order_relaxed);
        drop(std::move(sample), core::DropReason::write_failed);
        return false;
    }
    processing_latency_.record(clock_.now() - sample.arrival);
    return true;
}

void GatewaySink::drop(core::Sample&& sample, core::DropReason reason) {
    if (log_ == nullptr || sample.topic == status_topic_) {
        return;
    }
    log::LogRecord record;
    if (const TopicBridge* bridge = topics_.find(sample.topic)) {
        record.topic = bridge->name();
        record.type_name = bridge->type_name();
    }
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
