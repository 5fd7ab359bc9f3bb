#include "gateway/core/forwarding_loop.hpp"

#include <utility>

namespace tgw::core {

ForwardingLoop::ForwardingLoop(const SchedulerConfig& config, const base::Clock& clock, SampleSink& sink)
    : clock_(clock), sink_(sink), scheduler_(config) {}

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
    std::lock_guard<std::mutex> lock(mutex_);
    scheduler_.drain(sink_, DropReason::shutdown);
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
    std::lock_guard<std::mutex> lock(mutex_);
    return scheduler_.retire_topic(topic, reusable);
}

void ForwardingLoop::set_ttl(TopicId topic, base::Duration ttl) {
    std::lock_guard<std::mutex> lock(mutex_);
    scheduler_.set_ttl(topic, ttl);
}

void ForwardingLoop::submit(Sample&& sample) {
    std::lock_guard<std::mutex> lock(mutex_);
    {
        if (stopped_) {
            // Arrived after shutdown drained the queue: still logged, never lost.
            scheduler_.push(std::move(sample), clock_.now(), clock_.wall_now(), sink_);
            scheduler_.drain(sink_, DropReason::shutdown);
            return;
        }
        const base::SteadyTime now = clock_.now();
        scheduler_.push(std::move(sample), now, clock_.wall_now(), sink_);
        scheduler_.release(now, sink_);
        // The loop thread must recompute its wake-up: the new sample may be due before what it waits for.
        if (scheduler_.queued_samples() > 0) {
            kick_nts();
        }
    }
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

void ForwardingLoop::kick_nts() {
    kicked_ = true;
    wake_.notify_one();
}

void ForwardingLoop::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
        const base::SteadyTime now = clock_.now();
        scheduler_.release(now, sink_);
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
