#include "gateway/dds/gateway_sink.hpp"

#include <utility>

#include "gateway/dds/backfill_sender.hpp"
#include "gateway/dds/compact_wan.hpp"
#include "gateway/dds/repair_desk.hpp"
#include "wire/backfill_codec.hpp"

namespace tgw::dds {

GatewaySink::GatewaySink(const TopicTable& topics, log::RobotLog* log, const base::Clock& clock)
    : topics_(topics), log_(log), clock_(clock) {}

void GatewaySink::set_status_route(core::TopicId id, std::shared_ptr<WanWriter> writer) {
    status_topic_ = id;
    status_writer_ = std::move(writer);
}

void GatewaySink::set_backfill_route(core::TopicId id, std::shared_ptr<WanWriter> writer, BackfillSender* sender) {
    backfill_topic_ = id;
    backfill_writer_ = std::move(writer);
    backfill_ = sender;
}

bool GatewaySink::forward(core::Sample&& sample) {
    if (sample.topic == backfill_topic_) {
        // A backfill sample's fragments, when paced, are the schedule's too; it counts as left once it is written.
        const bool written = backfill_writer_ != nullptr && backfill_writer_->write(sample) == WriteResult::ok;
        if (!written) {
            wan_write_failures_.fetch_add(1, std::memory_order_relaxed);
        }
        backfill_left(sample, written);
        return written;
    }
    WriteResult result = WriteResult::unknown_topic;
    const std::size_t payload_bytes = sample.payload.size();  // a latched writer may take the payload
    const bool status = sample.topic == status_topic_;
    std::shared_ptr<TopicBridge> bridge = status ? nullptr : topics_.find(sample.topic);
    const RepairDesk::PacedWatch paced;
    if (status) {
        result = status_writer_->write(sample);
    } else if (bridge != nullptr) {
        result = bridge->write(sample, AfterWrite::payload_spent);
    }
    if (result != WriteResult::ok) {
        // The payload is still ours: keep it, so that a refused write is never silently lost.
        wan_write_failures_.fetch_add(1, std::memory_order_relaxed);
        drop(std::move(sample), core::DropReason::write_failed);
        return false;
    }
    const base::SteadyTime written = clock_.now();
    processing_latency_.record(written - sample.arrival);
    if (paced.sample() != 0 && log_ != nullptr && bridge != nullptr) {
        std::lock_guard<std::mutex> lock(paced_mutex_);
        prune_paced_nts(written);
        paced_[paced.sample()] = PacedSample{std::move(sample), std::move(bridge), paced.continuations()};
        return true;
    }
    log_forwarded(sample, bridge.get(), written, payload_bytes);
    return true;
}

std::size_t GatewaySink::forward_bundle(std::vector<core::Sample>&& samples, std::size_t wire_bytes) {
    core::EncodedBundle bundle;
    const std::size_t written = encode_bundle(samples, wire_bytes, bundle);
    return written > 0 && write_bundle(std::move(samples), std::move(bundle)) ? written : 0;
}

std::size_t GatewaySink::encode_bundle(std::vector<core::Sample>& samples, std::size_t /*wire_bytes*/,
                                       core::EncodedBundle& out) {
    if (compact_ == nullptr) {
        return 0;
    }
    return compact_->encode(samples, out);
}

bool GatewaySink::write_bundle(std::vector<core::Sample>&& samples, core::EncodedBundle&& bundle) {
    const bool written = compact_ != nullptr && compact_->send(std::move(bundle), samples.size());
    for (core::Sample& sample : samples) {
        // A chunk is a piece of a sample the scheduler keeps whole: it logs the sample if the chunks fail, and the
        // sample has left once its last chunk has.
        if (sample.topic == backfill_topic_) {
            backfill_left(sample, written);
            continue;
        }
        if (!written) {
            wan_write_failures_.fetch_add(1, std::memory_order_relaxed);
            if (!sample.chunk) {
                drop(std::move(sample), core::DropReason::write_failed);
            }
        } else if (sample.completes_sample()) {
            const base::SteadyTime now = clock_.now();
            processing_latency_.record(now - sample.arrival);
            log_forwarded(sample, sample.topic == status_topic_ ? nullptr : topics_.find(sample.topic).get(), now);
        }
    }
    return written;
}

void GatewaySink::log_forwarded(const core::Sample& sample, const TopicBridge* bridge, base::SteadyTime written,
                                std::optional<std::size_t> payload_bytes) {
    // The log says what left the robot, so that the mission archive can tell lost on the link from never produced.
    // Not the status (the gateway's own, not telemetry), nor a dispose or unregister: the base camp records data
    // samples only, so one could never be matched.
    if (log_ != nullptr && bridge != nullptr && sample.kind == core::SampleKind::data) {
        // One reading of each clock for the three times: this runs for every sample sent.
        const base::WallTime written_wall = clock_.wall_now();
        const auto wall = [&](base::SteadyTime t) {
            return written_wall + std::chrono::duration_cast<base::WallClock::duration>(t - written);
        };
        log::ForwardRecord record;
        record.topic = bridge->wan_name();  // as the base camp records it: merge and report match on it
        record.type_name = bridge->type_name();
        record.sample = &sample;
        record.payload_bytes = payload_bytes;
        record.arrival = wall(sample.arrival);
        record.deadline = wall(sample.deadline);
        record.forwarded_at = written_wall;
        log_->append_forwarded(record);
    }
}

void GatewaySink::send_repair(std::uint64_t id) {
    if (repairs_ == nullptr) {
        return;
    }
    if (const std::uint64_t sample = repairs_->send(id); sample != 0) {
        paced_fragment_left(sample);
    }
}

void GatewaySink::paced_fragment_left(std::uint64_t sample) {
    PacedSample left;
    {
        std::lock_guard<std::mutex> lock(paced_mutex_);
        const auto it = paced_.find(sample);
        if (it == paced_.end() || --it->second.fragments_left > 0) {
            return;
        }
        left = std::move(it->second);
        paced_.erase(it);
    }
    log_forwarded(left.sample, left.bridge.get(), clock_.now());
}

void GatewaySink::sample_cut_short(std::uint64_t sample, core::DropReason reason) {
    PacedSample cut;
    {
        std::lock_guard<std::mutex> lock(paced_mutex_);
        const auto it = paced_.find(sample);
        if (it == paced_.end()) {
            return;  // not kept: no log
        }
        cut = std::move(it->second);
        paced_.erase(it);
    }
    drop(std::move(cut.sample), reason);
}

void GatewaySink::prune_paced_nts(base::SteadyTime now) {
    // Each fragment is sent or cut short before its sample's deadline; a grace for the decision in flight.
    constexpr std::chrono::seconds GRACE{5};
    if (now < next_paced_prune_) {
        return;
    }
    next_paced_prune_ = now + std::chrono::seconds(1);
    for (auto it = paced_.begin(); it != paced_.end();) {
        if (it->second.sample.deadline + GRACE < now) {
            log_forwarded(it->second.sample, it->second.bridge.get(), now);
            it = paced_.erase(it);
        } else {
            ++it;
        }
    }
}

void GatewaySink::discard_repair(std::uint64_t id) {
    if (repairs_ != nullptr) {
        repairs_->discard(id);
    }
}

void GatewaySink::backfill_left(const core::Sample& sample, bool written) {
    std::optional<std::int64_t> row;
    if (!sample.chunk || sample.chunk->offset == 0) {
        row = wire::backfill_row_id(sample.payload);
    }
    if (sample.chunk) {
        // The sample is told whole: left with its last chunk; if a chunk fails, the scheduler drops it whole.
        if (row) {
            backfill_chunks_[sample.chunk->id] = *row;
        }
        const auto it = backfill_chunks_.find(sample.chunk->id);
        if (it == backfill_chunks_.end() || !sample.completes_sample()) {
            return;
        }
        row = it->second;
        backfill_chunks_.erase(it);
        if (written) {
            backfill_->left(*row, sample.chunk->total_bytes);
        }
        return;
    }
    if (row && written) {
        backfill_->left(*row, sample.payload.size());
    } else if (row) {
        backfill_->not_left(*row);
    }
}

void GatewaySink::drop(core::Sample&& sample, core::DropReason reason) {
    if (sample.topic == backfill_topic_) {
        // Its row is in the log already: it may go again.
        if (const std::optional<std::int64_t> row = wire::backfill_row_id(sample.payload)) {
            backfill_->not_left(*row);
        }
        return;
    }
    if (log_ == nullptr || sample.topic == status_topic_) {
        return;
    }
    log::LogRecord record;
    if (const std::shared_ptr<TopicBridge> bridge = topics_.find(sample.topic)) {
        record.topic = bridge->wan_name();  // as the base camp records it: merge and report match on it
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

base::WallTime GatewaySink::to_wall(base::SteadyTime t) const {
    return clock_.wall_now() + std::chrono::duration_cast<base::WallClock::duration>(t - clock_.now());
}

}  // namespace tgw::dds
