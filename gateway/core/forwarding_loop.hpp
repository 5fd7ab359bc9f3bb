#pragma once

#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "base/clock.hpp"
#include "gateway/core/scheduler.hpp"

namespace tgw::core {

/// Runs a Scheduler for the gateway: DDS listener threads submit samples, which are released at once
/// in the submitting thread when the budget admits them (no thread hop on the fast path); one thread wakes
/// when the scheduler asks to (link free again, a deadline) and releases or logs what is due. Every call into
/// the scheduler and the sink happens under one lock, so the sink need not be thread-safe.
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
    /// See Scheduler::retire_topic.
    std::optional<TopicCounters> retire_topic(TopicId topic, bool reusable);
    void set_ttl(TopicId topic, base::Duration ttl);
    void submit(Sample&& sample);
    void set_rate(double rate_bps);
    /// See Scheduler::set_reachable.
    void set_reachable(TopicId topic, bool reachable);
    /// See Scheduler::charge_link.
    void charge_link(std::uint64_t bits);
    /// See Scheduler::observe_link_backlog.
    void observe_link_backlog(std::uint64_t bits);

    TopicCounters counters(TopicId topic) const;
    TopicCounters total_counters() const;
    double rate_bps() const;
    std::size_t queued_samples() const;
    /// Topics not retired (Scheduler::live_topics).
    std::size_t live_topics() const;

  private:
    void run();
    void kick_nts();  // the lock is held

    const base::Clock& clock_;
    SampleSink& sink_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    Scheduler scheduler_;
    std::thread thread_;
    bool kicked_ = false;
    bool stopping_ = false;
    bool stopped_ = false;
};

}  // namespace tgw::core
