#pragma once

#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "base/clock.hpp"
#include "core/scheduler.hpp"
#include "core/write_outbox.hpp"

namespace tgw::core {

/// Runs a Scheduler for the gateway: DDS listener threads submit samples, which are released at once
/// in the submitting thread when the budget admits them (no thread hop on the fast path); one thread wakes
/// when the scheduler asks to (link free again, a deadline) and releases or logs what is due.
///
/// Every call into the scheduler happens under one lock; the sink is called by one thread at a time, in the
/// order the scheduler decided. The decisions go into a WriteOutbox under the lock and are written after it: a
/// WAN write that blocks then holds up only the thread writing, never a listener that brings a sample while it
/// writes (it finds the writer busy, leaves its decisions to it and returns). In compact mode
/// (SchedulerConfig::bundles) the sink encodes each bundle under the lock, so that the budget charges its real
/// size, and writes it after. A write that fails is settled with the scheduler afterwards: the sample counts as
/// write_failed, and a sample sent in chunks is logged whole if any of its chunks failed.
class ForwardingLoop {
  public:
    ForwardingLoop(const SchedulerConfig& config, const base::Clock& clock, SampleSink& sink);
    ~ForwardingLoop();

    ForwardingLoop(const ForwardingLoop&) = delete;
    ForwardingLoop& operator=(const ForwardingLoop&) = delete;

    void start();
    /// Stops the thread and writes everything still queued to the sink as `shutdown`. Idempotent.
    void stop();

    TopicId add_topic(const TopicConfig& topic);
    /// See Scheduler::add_topic_at.
    bool add_topic_at(TopicId slot, const TopicConfig& topic);
    /// See Scheduler::retire_topic; waits until what was decided is written. Not from within the sink.
    std::optional<TopicCounters> retire_topic(TopicId topic, bool reusable);
    void set_ttl(TopicId topic, base::Duration ttl);
    void submit(Sample&& sample);
    /// See Scheduler::push_repair. Decides nothing in the calling thread (Fast DDS's, holding its writer's lock):
    /// the loop's thread sends or discards it.
    void submit_repair(const Repair& repair);
    RepairCounters repair_counters() const;
    /// See Scheduler::set_rate.
    void set_rate(double rate_bps, double steady_outside_bps = 0.0);
    /// See Scheduler::set_reachable.
    void set_reachable(TopicId topic, bool reachable);
    /// See Scheduler::set_idle_source. The source wakes the loop (kick()) when it has samples again after saying
    /// it had none.
    void set_idle_source(IdleSource* source, TopicId topic);
    /// Makes the loop's thread release now.
    void kick();
    /// See Scheduler::charge_link.
    void charge_link(std::uint64_t bits);
    /// Charges `bits` that a write of this loop's decisions put on the link beyond what the scheduler charged for
    /// it (a reliable writer's HEARTBEAT, a sample's copy to a second reader), when the calling thread is the one
    /// writing them: the charge then waits for the lock the writing thread takes again after the write, before
    /// any further decision, and no other thread is woken for it. False in any other thread: nothing charged.
    bool charge_link_from_write(std::uint64_t bits);
    /// See Scheduler::observe_link_backlog.
    void observe_link_backlog(std::uint64_t bits);

    TopicCounters counters(TopicId topic) const;
    TopicCounters total_counters() const;
    double rate_bps() const;
    std::size_t queued_samples() const;
    /// Topics not retired (Scheduler::live_topics).
    std::size_t live_topics() const;

  private:
    /// Where the scheduler's decisions go while the lock is held.
    SampleSink& decisions() { return outbox_; }
    /// Writes the outbox to the sink, releasing `lock` meanwhile, until it stays empty; returns at once when
    /// another thread is writing (it takes what was added). `lock` is held on entry and on return.
    void write_outbox(std::unique_lock<std::mutex>& lock);
    /// The writing thread's, without the lock: writes writing_now_ and notes what failed.
    void write_decisions();
    void write_bundle(WriteOutbox::BundleWrite& bundle);
    /// The writing thread's, under the lock: tells the scheduler what failed, and what the writes charged.
    void settle_writes();
    void run();
    void kick_nts();  // the lock is held

    const base::Clock& clock_;
    SampleSink& sink_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    Scheduler scheduler_;
    WriteOutbox outbox_;    // under mutex_
    bool writing_ = false;  // under mutex_: a thread is writing the outbox to the sink
    // The rest is the writing thread's, while writing_.
    std::vector<WriteOutbox::Decision> writing_now_;
    /// What the writes of writing_now_ charged (charge_link_from_write), for the scheduler once the lock is back.
    std::uint64_t write_charge_bits_ = 0;
    /// A write that failed, to settle with the scheduler.
    struct FailedWrite {
        enum class Kind : std::uint8_t {
            sample,        ///< forward() failed
            bundle_entry,  ///< a whole sample in a bundle that failed, or a chunked one a chunk of which did
            chunk,         ///< a chunk in a bundle that failed
        };
        Kind kind;
        TopicId topic;
        std::size_t payload_bytes;
        std::uint64_t wire_bytes;  ///< bundle_entry: its share of the bundle
        std::uint32_t chunk_id;    ///< chunk
    };
    std::vector<FailedWrite> failed_;
    /// Chunk ids (Sample::Chunk::id) of samples a chunk of which failed after the scheduler let them go.
    std::vector<std::uint32_t> failed_chunks_;
    std::condition_variable written_;  // writing_ went false
    std::thread thread_;
    bool kicked_ = false;
    bool stopping_ = false;
    bool stopped_ = false;
};

}  // namespace tgw::core
