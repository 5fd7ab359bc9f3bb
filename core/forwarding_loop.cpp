#include "core/forwarding_loop.hpp"

#include <algorithm>
#include <utility>

namespace tgw::core {

namespace {

/// The loop whose decisions this thread is writing, if any (charge_link_from_write).
thread_local const ForwardingLoop* loop_writing_here = nullptr;

/// Marks the calling thread as writing `loop`'s decisions while it lives.
class WritingHere {
  public:
    explicit WritingHere(const ForwardingLoop* loop) : before_(loop_writing_here) { loop_writing_here = loop; }
    ~WritingHere() { loop_writing_here = before_; }
    WritingHere(const WritingHere&) = delete;
    WritingHere& operator=(const WritingHere&) = delete;

  private:
    const ForwardingLoop* before_;
};

}  // namespace

ForwardingLoop::ForwardingLoop(const SchedulerConfig& config, const base::Clock& clock, SampleSink& sink)
    : clock_(clock), sink_(sink), scheduler_(config), outbox_(sink) {}

ForwardingLoop::~ForwardingLoop() {
    stop();
}

void ForwardingLoop::start() {
    thread_ = std::thread([this] { run(); });
}

void ForwardingLoop::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopped_)
            return;
        stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable())
        thread_.join();
    std::unique_lock<std::mutex> lock(mutex_);
    scheduler_.drain(decisions(), DropReason::shutdown);
    write_outbox(lock);
    written_.wait(lock, [this] { return !writing_ && outbox_.empty(); });
    stopped_ = true;
}

TopicId ForwardingLoop::add_topic(const TopicConfig& topic) {
    std::lock_guard<std::mutex> lock(mutex_);
    return scheduler_.add_topic(topic);
}

bool ForwardingLoop::add_topic_at(TopicId slot, const TopicConfig& topic) {
    std::lock_guard<std::mutex> lock(mutex_);
    return scheduler_.add_topic_at(slot, topic);
}

std::optional<TopicCounters> ForwardingLoop::retire_topic(TopicId topic, bool reusable) {
    std::unique_lock<std::mutex> lock(mutex_);
    // A decision of the topic may still be on its way to the sink, which finds the topic by its id: the id must
    // not go (nor be taken by another topic) before it is written, and its write settled.
    written_.wait(lock, [this] { return !writing_ && outbox_.empty(); });
    return scheduler_.retire_topic(topic, reusable);
}

void ForwardingLoop::set_ttl(TopicId topic, base::Duration ttl) {
    std::lock_guard<std::mutex> lock(mutex_);
    scheduler_.set_ttl(topic, ttl);
}

void ForwardingLoop::submit(Sample&& sample) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (stopped_) {
        // Arrived after shutdown drained the queue: still logged, never lost.
        scheduler_.push(std::move(sample), clock_.now(), clock_.wall_now(), decisions());
        scheduler_.drain(decisions(), DropReason::shutdown);
    } else {
        const base::SteadyTime now = clock_.now();
        scheduler_.push(std::move(sample), now, clock_.wall_now(), decisions());
        scheduler_.release(now, decisions());
        // The loop thread must recompute its wake-up: the new sample may be due before what it waits for.
        if (scheduler_.queued_samples() > 0) {
            kick_nts();
        }
    }
    write_outbox(lock);
}

void ForwardingLoop::submit_repair(const Repair& repair) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (stopped_) {
        // Never sent after shutdown; a sample cut short by it is logged, as the queue's were.
        scheduler_.discard_repair(repair, DropReason::shutdown, decisions());
        write_outbox(lock);
        return;
    }
    scheduler_.push_repair(repair, clock_.now(), decisions());
    kick_nts();
}

void ForwardingLoop::set_idle_source(IdleSource* source, TopicId topic) {
    std::lock_guard<std::mutex> lock(mutex_);
    scheduler_.set_idle_source(source, topic);
    kick_nts();
}

void ForwardingLoop::kick() {
    std::lock_guard<std::mutex> lock(mutex_);
    kick_nts();
}

RepairCounters ForwardingLoop::repair_counters() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return scheduler_.repair_counters();
}

void ForwardingLoop::set_rate(double rate_bps, double steady_outside_bps) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        scheduler_.set_rate(rate_bps, steady_outside_bps);
        kick_nts();
    }
}

void ForwardingLoop::set_reachable(TopicId topic, bool reachable) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (scheduler_.reachable(topic) != reachable) {
        scheduler_.set_reachable(topic, reachable);
        kick_nts();  // what waited for a reader may go now
    }
}

void ForwardingLoop::charge_link(std::uint64_t bits) {
    std::lock_guard<std::mutex> lock(mutex_);
    scheduler_.charge_link(clock_.now(), bits);
}

bool ForwardingLoop::charge_link_from_write(std::uint64_t bits) {
    if (loop_writing_here != this) {
        return false;
    }
    // Only the writing thread touches it until it takes the lock again and settles it.
    write_charge_bits_ += bits;
    return true;
}

void ForwardingLoop::observe_link_backlog(std::uint64_t bits) {
    std::lock_guard<std::mutex> lock(mutex_);
    scheduler_.observe_link_backlog(clock_.now(), bits);
}

TopicCounters ForwardingLoop::counters(TopicId topic) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return scheduler_.counters(topic);
}

TopicCounters ForwardingLoop::total_counters() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return scheduler_.total_counters();
}

double ForwardingLoop::rate_bps() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return scheduler_.rate_bps();
}

std::size_t ForwardingLoop::queued_samples() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return scheduler_.queued_samples();
}

std::size_t ForwardingLoop::live_topics() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return scheduler_.live_topics();
}

void ForwardingLoop::write_outbox(std::unique_lock<std::mutex>& lock) {
    if (writing_) {
        return;  // the writing thread takes what was just added, after what it is writing
    }
    writing_ = true;
    while (!outbox_.empty()) {
        outbox_.take(writing_now_);
        lock.unlock();
        {
            const WritingHere here(this);
            write_decisions();
        }
        lock.lock();
        settle_writes();
    }
    writing_ = false;
    written_.notify_all();
}

void ForwardingLoop::write_decisions() {
    for (WriteOutbox::Decision& d : writing_now_) {
        switch (d.kind) {
            case WriteOutbox::Decision::Kind::drop:
                sink_.drop(std::move(d.sample), d.reason);
                break;
            case WriteOutbox::Decision::Kind::forward: {
                const FailedWrite f{FailedWrite::Kind::sample, d.sample.topic, d.sample.payload.size(), 0, 0};
                if (!sink_.forward(std::move(d.sample))) {
                    failed_.push_back(f);
                }
                break;
            }
            case WriteOutbox::Decision::Kind::bundle:
                write_bundle(*d.bundle);
                break;
            case WriteOutbox::Decision::Kind::send_repair:
                sink_.send_repair(d.repair_id);
                break;
            case WriteOutbox::Decision::Kind::discard_repair:
                sink_.discard_repair(d.repair_id);
                break;
            case WriteOutbox::Decision::Kind::sample_cut_short:
                sink_.sample_cut_short(d.repair_id, d.reason);
                break;
        }
    }
}

void ForwardingLoop::write_bundle(WriteOutbox::BundleWrite& d) {
    // What settling a failure needs, read before the sink takes the samples.
    std::uint64_t payload_bytes = 0;
    std::optional<std::uint32_t> completed_id;  // of the sample whose last chunk this is
    for (const Sample& s : d.entries) {
        payload_bytes += s.payload.size();
        if (s.chunk && s.completes_sample()) {
            completed_id = s.chunk->id;
        }
    }
    const std::size_t settled_before = failed_.size();
    BundleShares shares(d.encoded.wire_bytes, payload_bytes, d.entries.size());
    for (const Sample& s : d.entries) {
        const std::uint64_t share = shares.next(s.payload.size());
        if (s.chunk) {
            failed_.push_back(FailedWrite{FailedWrite::Kind::chunk, s.topic, 0, 0, s.chunk->id});
        } else {
            failed_.push_back(FailedWrite{FailedWrite::Kind::bundle_entry, s.topic, s.payload.size(), share, 0});
        }
    }
    if (sink_.write_bundle(std::move(d.entries), std::move(d.encoded))) {
        failed_.resize(settled_before);
    } else {
        for (std::size_t i = settled_before; i < failed_.size(); ++i) {
            if (failed_[i].kind == FailedWrite::Kind::chunk) {
                failed_chunks_.push_back(failed_[i].chunk_id);
            }
        }
    }
    if (d.completed && completed_id) {
        // The scheduler counted the sample forwarded when it decided its last chunk. If one of its chunks, this or
        // an earlier, was not written, it cannot arrive whole: it is logged whole.
        const auto failed = std::find(failed_chunks_.begin(), failed_chunks_.end(), *completed_id);
        if (failed != failed_chunks_.end()) {
            failed_chunks_.erase(failed);
            const std::size_t bytes = d.completed->payload.size();
            failed_.push_back(FailedWrite{FailedWrite::Kind::bundle_entry, d.completed->topic, bytes, 0, 0});
            sink_.drop(std::move(*d.completed), DropReason::write_failed);
        }
    }
    // Ids of samples long gone (abandoned meanwhile by the scheduler) are not kept for ever.
    constexpr std::size_t MAX_FAILED_CHUNKS = 16;
    if (failed_chunks_.size() > MAX_FAILED_CHUNKS) {
        failed_chunks_.erase(failed_chunks_.begin());
    }
}

void ForwardingLoop::settle_writes() {
    for (const FailedWrite& f : failed_) {
        switch (f.kind) {
            case FailedWrite::Kind::sample:
                scheduler_.forward_failed(f.topic, f.payload_bytes);
                break;
            case FailedWrite::Kind::bundle_entry:
                scheduler_.forward_failed(f.topic, f.payload_bytes, f.wire_bytes);
                break;
            case FailedWrite::Kind::chunk:
                // Still leaving in chunks: abandoned now, logged through the outbox. Else it left already, and its
                // last chunk's bundle settles it.
                if (scheduler_.chunk_failed(f.chunk_id, outbox_)) {
                    failed_chunks_.erase(std::remove(failed_chunks_.begin(), failed_chunks_.end(), f.chunk_id),
                                         failed_chunks_.end());
                }
                break;
        }
    }
    failed_.clear();
    if (write_charge_bits_ > 0) {
        scheduler_.charge_link(clock_.now(), write_charge_bits_);
        write_charge_bits_ = 0;
    }
}

void ForwardingLoop::kick_nts() {
    kicked_ = true;
    wake_.notify_one();
}

void ForwardingLoop::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
        const base::SteadyTime now = clock_.now();
        scheduler_.release(now, decisions());
        if (!outbox_.empty() && !writing_) {
            write_outbox(lock);
            continue;  // writing took time: the link may take more already
        }
        const auto next = scheduler_.next_wakeup(now);
        // The clock is injected, but waiting needs real time: sleep for the span the scheduler asked for.
        if (next) {
            wake_.wait_for(lock, *next - now, [this] { return stopping_ || kicked_; });
        } else {
            wake_.wait(lock, [this] { return stopping_ || kicked_; });
        }
        kicked_ = false;
    }
}

}  // namespace tgw::core
