#include "gateway/core/forwarding_loop.hpp"

#include <utility>

namespace tgw::core {

ForwardingLoop::ForwardingLoop(const SchedulerConfig& config, const base::Clock& clock, SampleSink& sink)
    : clock_(clock), sink_(sink), scheduler_(config), defer_writes_(!config.bundles) {}

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

void ForwardingLoop::set_rate(double rate_bps) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        scheduler_.set_rate(rate_bps);
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
        struct Failed {
            TopicId topic;
            std::size_t payload_bytes;
        };
        std::vector<Failed> failed;  // rare: allocates only when a write fails
        for (WriteOutbox::Decision& d : writing_now_) {
            if (!d.forward) {
                sink_.drop(std::move(d.sample), d.reason);
                continue;
            }
            const Failed f{d.sample.topic, d.sample.payload.size()};
            if (!sink_.forward(std::move(d.sample))) {
                failed.push_back(f);
            }
        }
        lock.lock();
        for (const Failed& f : failed) {
            scheduler_.forward_failed(f.topic, f.payload_bytes);
        }
    }
    writing_ = false;
    written_.notify_all();
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
