#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_map>

#include "base/clock.hpp"
#include "core/latency_histogram.hpp"
#include "core/sample_sink.hpp"
#include "gateway/dds/topic_table.hpp"
#include "gateway/log/robot_log.hpp"

namespace tgw::dds {

class BackfillSender;
class CompactWan;
class RepairDesk;

/// Where the scheduler's decisions land in the gateway: released samples are written to the WAN by their topic's
/// bridge, the others
/// appended to the on-robot log (when there is one) with their steady times converted to wall time here, at
/// the edge. Never throws; failures are counted.
class GatewaySink final : public core::SampleSink {
  public:
    /// `log` may be null (no --log): dropped samples are then only counted.
    GatewaySink(const TopicTable& topics, log::RobotLog* log, const base::Clock& clock);

    /// Samples of topic `id` are the gateway's own status, written through `writer`; one that misses its
    /// deadline is not logged (the next status carries its counts). Call before the loop starts.
    void set_status_route(core::TopicId id, std::shared_ptr<WanWriter> writer);

    /// Samples of topic `id` are backfill (BackfillSender's): written through `writer`, their fate told to `sender`
    /// (which must outlive the sink), never logged: their rows are in the log already. Call before the loop starts.
    void set_backfill_route(core::TopicId id, std::shared_ptr<WanWriter> writer, BackfillSender* sender);

    /// Compact WAN mode: bundles go through `compact`, which must outlive the sink. Call before the loop starts.
    void set_compact(CompactWan* compact) { compact_ = compact; }

    bool forward(core::Sample&& sample) override;
    std::size_t forward_bundle(std::vector<core::Sample>&& samples, std::size_t wire_bytes) override;
    std::size_t encode_bundle(std::vector<core::Sample>& samples, std::size_t wire_bytes,
                              core::EncodedBundle& out) override;
    bool write_bundle(std::vector<core::Sample>&& samples, core::EncodedBundle&& bundle) override;
    void drop(core::Sample&& sample, core::DropReason reason) override;
    void send_repair(std::uint64_t id) override;
    void discard_repair(std::uint64_t id) override;
    void sample_cut_short(std::uint64_t sample, core::DropReason reason) override;

    /// Repairs the scheduler decides on are `desk`'s, which must outlive the sink. Call before the loop starts.
    void set_repair_desk(RepairDesk* desk) { repairs_ = desk; }

    std::uint64_t wan_write_failures() const { return wan_write_failures_.load(); }
    std::uint64_t logged() const { return logged_.load(); }
    /// The gateway's own time per forwarded sample: from its arrival (Scheduler::push) to the return of the
    /// WAN write. Failed writes are not counted.
    const core::LatencyHistogram& processing_latency() const { return processing_latency_; }

  private:
    /// The on-robot log's record of a sample that left for the WAN at `written` (clock_'s now). `bridge`: its
    /// topic's, null for the status.
    /// `payload_bytes`: the sample's, when a latched writer took its payload.
    void log_forwarded(const core::Sample& sample, const TopicBridge* bridge, base::SteadyTime written,
                       std::optional<std::size_t> payload_bytes = std::nullopt);
    /// A sample whose fragments after the first the RepairDesk paced (core::Repair::Kind::continuation): it has
    /// left once its last fragment has, and is logged then; cut short, it is kept with its reason instead.
    struct PacedSample {
        core::Sample sample;
        std::shared_ptr<TopicBridge> bridge;
        std::size_t fragments_left = 0;
    };
    /// One of the paced sample's fragments left.
    void paced_fragment_left(std::uint64_t sample);
    /// Logs as forwarded, and forgets, the paced samples well past their deadlines: their fragments were forgotten
    /// with the WAN participant (made anew), having left in part. The lock is held.
    void prune_paced_nts(base::SteadyTime now);
    base::WallTime to_wall(base::SteadyTime t) const;

    const TopicTable& topics_;
    std::optional<core::TopicId> status_topic_;
    std::shared_ptr<WanWriter> status_writer_;
    std::optional<core::TopicId> backfill_topic_;
    std::shared_ptr<WanWriter> backfill_writer_;
    BackfillSender* backfill_ = nullptr;
    /// Compact mode: the rows of backfill samples leaving in chunks, by chunk id (read from the first chunk, which
    /// begins with the row id). Written by one thread at a time, as every decision.
    std::unordered_map<std::uint32_t, std::int64_t> backfill_chunks_;
    /// A backfill sample (or its first chunk) left, or not.
    void backfill_left(const core::Sample& sample, bool written);
    CompactWan* compact_ = nullptr;
    RepairDesk* repairs_ = nullptr;
    log::RobotLog* log_;
    const base::Clock& clock_;
    std::atomic<std::uint64_t> wan_write_failures_{0};
    std::atomic<std::uint64_t> logged_{0};
    core::LatencyHistogram processing_latency_;
    std::mutex paced_mutex_;
    std::unordered_map<std::uint64_t, PacedSample> paced_;  ///< by core::Repair::sample
    base::SteadyTime next_paced_prune_{};
};

}  // namespace tgw::dds
