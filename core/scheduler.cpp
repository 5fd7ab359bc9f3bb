#include "core/scheduler.hpp"

#include <algorithm>
#include <optional>
#include <utility>

namespace tgw::core {

Scheduler::Scheduler(const SchedulerConfig& config)
    : config_(config),
      sensed_rate_bps_(config.initial_rate_bps),
      budget_(config.initial_rate_bps * config.budget_fraction, config.lead),
      reserve_(config.reserve_window),
      paper_(config.paper_period, config.paper_overhead) {
    if (config.bundles)
        chunk_planning_.emplace(config.wire, *config.bundles, config.link_latency);
}

void Scheduler::set_rate(double sensed_rate_bps, double steady_outside_bps) {
    sensed_rate_bps_ = sensed_rate_bps;
    const double budget_rate_bps = std::max(sensed_rate_bps * config_.budget_fraction - steady_outside_bps,
                                            sensed_rate_bps * config_.budget_fraction * MIN_SCHEDULED_SHARE);
    if (budget_rate_bps != budget_.rate_bps()) {
        budget_.set_rate(budget_rate_bps);
        protect_valid_ = false;  // the limits are in wire time at the rate
    }
}

TopicId Scheduler::add_topic(const TopicConfig& topic) {
    if (!free_topics_.empty()) {
        const TopicId slot = free_topics_.back();
        add_topic_at(slot, topic);
        return slot;
    }
    topics_.push_back(fresh_topic(topic));
    return static_cast<TopicId>(topics_.size() - 1);
}

bool Scheduler::add_topic_at(TopicId slot, const TopicConfig& topic) {
    if (slot >= topics_.size() || !topics_[slot].retired) {
        return false;
    }
    free_topics_.erase(std::remove(free_topics_.begin(), free_topics_.end(), slot), free_topics_.end());
    --retired_slots_;
    topics_[slot] = fresh_topic(topic);
    return true;
}

Scheduler::TopicState Scheduler::fresh_topic(const TopicConfig& topic) {
    TopicState state;
    state.config = topic;
    if (topic.max_rate_hz > 0.0)
        state.rate_cap.emplace(topic.max_rate_hz);
    return state;
}

std::optional<TopicCounters> Scheduler::retire_topic(TopicId topic, bool reusable) {
    if (topic >= topics_.size() || topics_[topic].retired || topics_[topic].counters.queued > 0) {
        return std::nullopt;  // a chunked sample counts as queued until its last chunk left
    }
    TopicState& t = topics_[topic];
    const TopicCounters final_counts = t.counters;
    retired_counters_ += final_counts;
    queue_.park(topic, false);
    if (t.config.latest_only)
        latest_.forget_topic(topic);
    TopicState emptied;
    emptied.config.ttl = t.config.ttl;
    emptied.retired = true;
    t = std::move(emptied);
    ++retired_slots_;
    if (reusable) {
        free_topics_.push_back(topic);
    }
    protect_valid_ = false;  // it may have been one of the two protected topics
    return final_counts;
}

void Scheduler::set_ttl(TopicId topic, base::Duration ttl) {
    topics_[topic].config.ttl = ttl;
    protect_valid_ = false;
}

void Scheduler::set_reachable(TopicId topic, bool reachable) {
    if (topics_[topic].reachable == reachable) {
        return;
    }
    topics_[topic].reachable = reachable;
    queue_.park(topic, !reachable);
    protect_valid_ = false;  // a topic that cannot send protects no one
}

bool Scheduler::active(TopicId topic, base::SteadyTime now) const {
    const TopicState& t = topics_[topic];
    return t.seen && t.reachable && now - t.last_arrival <= t.config.ttl;
}

base::Duration Scheduler::protect_limit(TopicId topic) const {
    const TopicState& t = topics_[topic];
    return t.config.ttl - budget_.transmit_time(t.last_wire_bits);
}

const ProtectedTopics& Scheduler::protected_topics(base::SteadyTime now) {
    // Only a push (handled there), a TTL or a rate change can bring a topic in; the two fall out by going
    // inactive. Time running backwards could make topics active again.
    const bool still_valid = protect_valid_ && now >= protect_built_at_ &&
                             (protect_.first().topic == ProtectedTopics::NONE || active(protect_.first().topic, now)) &&
                             (protect_.second().topic == ProtectedTopics::NONE || active(protect_.second().topic, now));
    if (!still_valid) {
        protect_ = ProtectedTopics{};
        ++protect_epoch_;
        for (TopicId id = 0; id < topics_.size(); ++id) {
            if (active(id, now)) {
                protect_.offer({id, protect_limit(id), protect_rank_of(id)});
                topics_[id].protect_epoch = protect_epoch_;
            }
        }
        protect_valid_ = true;
        protect_built_at_ = now;
    }
    return protect_;
}

std::int64_t Scheduler::rank_of(TopicId topic) const {
    if (topics_[topic].config.first) {
        return -1;  // below every TTL's rank, and below edf's and fifo's 0
    }
    return protect_rank_of(topic);
}

std::int64_t Scheduler::rank_of(const Repair& repair) const {
    if (repair.kind != Repair::Kind::announcement) {
        return rank_of(repair.topic);
    }
    switch (config_.policy) {
        case PolicyKind::ttl:
        case PolicyKind::paper:
            return ANNOUNCEMENT_TTL.count();
        case PolicyKind::edf:
        case PolicyKind::fifo:
            break;
    }
    return 0;
}

base::Duration Scheduler::protect_limit_for(const Repair& repair) const {
    return repair.kind == Repair::Kind::announcement ? protect_.limit_for(ProtectedTopics::NONE, rank_of(repair))
                                                     : protect_limit_for(repair.topic);
}

std::int64_t Scheduler::protect_rank_of(TopicId topic) const {
    switch (config_.policy) {
        case PolicyKind::ttl:
        case PolicyKind::paper:
            return topics_[topic].config.ttl.count();
        case PolicyKind::edf:
        case PolicyKind::fifo:
            return 0;
    }
    return 0;
}

void Scheduler::push(Sample&& sample, base::SteadyTime now, base::WallTime wall_now, SampleSink& sink) {
    TopicState& topic = topics_[sample.topic];
    ++topic.counters.received;
    if (!topic.counters.first_received) {
        topic.counters.first_received = now;
    }
    sample.arrival = now;
    sample.sequence = next_sequence_++;
    // A sample cannot be born after it arrived: a source clock running ahead must not lengthen its life.
    base::SteadyTime origin = now;
    if (config_.trust_source_clock) {
        origin = std::min(now, now + std::chrono::duration_cast<base::Duration>(sample.source_time - wall_now));
        // `now` and `wall_now` are two clock reads, as far apart as a preemption between them: a burst's samples,
        // microseconds apart at their source, must not be born out of their order, or they leave out of it.
        if (topic.seen && sample.source_time >= topic.last_source_time) {
            origin = std::max(origin, topic.last_origin);
        }
        topic.last_source_time = sample.source_time;
        topic.last_origin = origin;
    }
    sample.deadline = origin + topic.config.ttl;
    // The operator's rule before any scheduling: a thinned-out sample is no part of the topic's demand.
    if (topic.rate_cap && sample.kind == SampleKind::data && !topic.rate_cap->admit(now)) {
        drop(std::move(sample), DropReason::rate_capped, sink);
        return;
    }
    const std::uint64_t wire_bits = alone_wire_bits(sample);
    const bool same_limit = topic.protect_epoch == protect_epoch_ && topic.last_wire_bits == wire_bits;
    topic.last_arrival = now;
    topic.last_wire_bits = wire_bits;
    topic.seen = true;
    // Offering a topic again with the limit it was last offered with changes nothing.
    if (protect_valid_ && !same_limit && topic.reachable) {
        protect_valid_ = protect_.update({sample.topic, protect_limit(sample.topic), protect_rank_of(sample.topic)});
        topic.protect_epoch = protect_epoch_;
    }

    if (config_.policy == PolicyKind::fifo) {
        if (!topic.reachable) {
            drop(std::move(sample), DropReason::no_reader, sink);
            return;
        }
        forward(std::move(sample), wire_bits, sink);
        return;
    }
    if (sample.deadline <= now) {
        drop(std::move(sample), DropReason::expired, sink);
        return;
    }
    const std::int64_t rank = rank_of(sample.topic);
    const bool latest_only = topic.config.latest_only && sample.kind == SampleKind::data;
    const TopicId id = sample.topic;
    const InstanceKey key = sample.key;
    const std::uint64_t sequence = sample.sequence;
    topic.counters.queued_payload_bytes += sample.payload.size();
    queued_first_ += topic.config.first ? 1 : 0;
    const DeadlineQueue::Slot slot = queue_.push(std::move(sample), rank);
    ++topic.counters.queued;
    if (latest_only) {
        // The instance's older sample, if it still waits, is replaced by this one.
        const std::optional<LatestSamples::Queued> older = latest_.exchange(id, key, {slot, sequence});
        if (older && queue_.holds(older->slot, older->sequence))
            drop(take(older->slot), DropReason::superseded, sink);
    }
    evict_over_cap(sink);
}

std::uint64_t Scheduler::alone_wire_bits(const Sample& sample) const {
    if (!config_.bundles) {
        return wire_bits(sample.payload.size());
    }
    return BundleBuilder(config_.wire)
        .alone_wire_bits(
            BundleBuilder::Entry::of(sample.topic, sample.route, sample.source_time, sample.payload, sample.key.valid));
}

void Scheduler::release(base::SteadyTime now, SampleSink& sink) {
    expire(now, sink);
    switch (config_.policy) {
        case PolicyKind::ttl:
        case PolicyKind::edf:
            release_by_deadline(now, sink);
            fill_idle(now, sink);
            break;
        case PolicyKind::paper:
            release_paper_period(now, sink);
            break;
        case PolicyKind::fifo:
            break;
    }
}

void Scheduler::set_idle_source(IdleSource* source, TopicId topic) {
    idle_ = source;
    idle_topic_ = topic;
}

void Scheduler::fill_idle(base::SteadyTime now, SampleSink& sink) {
    if (idle_ == nullptr || !topics_[idle_topic_].reachable) {
        return;
    }
    while (queue_.empty() && !chunked_ && repairs_.empty() && budget_.can_send(now)) {
        std::optional<Sample> sample = idle_->next_when_idle(now);
        if (!sample) {
            return;
        }
        sample->topic = idle_topic_;
        // Born now, whatever it carries: its deadline only orders it last and bounds its wait.
        const base::WallTime born = sample->source_time;
        push(std::move(*sample), now, born, sink);
        release_by_deadline(now, sink);
    }
}

std::optional<base::SteadyTime> Scheduler::idle_wakeup(base::SteadyTime now) const {
    if (idle_ == nullptr || !topics_[idle_topic_].reachable || budget_.rate_bps() <= 0.0 ||
        (config_.policy != PolicyKind::ttl && config_.policy != PolicyKind::edf)) {
        return std::nullopt;
    }
    const std::optional<base::SteadyTime> ready = idle_->next_ready(now);
    if (!ready) {
        return std::nullopt;
    }
    return std::max({now, *ready, budget_.next_send_time()});
}

Sample Scheduler::take(DeadlineQueue::Slot slot) {
    Sample sample = queue_.take(slot);
    queued_first_ -= topics_[sample.topic].config.first ? 1 : 0;
    TopicCounters& counters = topics_[sample.topic].counters;
    --counters.queued;
    counters.queued_payload_bytes -= sample.payload.size();
    return sample;
}

void Scheduler::forward(Sample&& sample, std::uint64_t wire_bits, SampleSink& sink) {
    TopicCounters& c = topics_[sample.topic].counters;
    const std::size_t payload_bytes = sample.payload.size();
    if (!sink.forward(std::move(sample))) {
        ++c.dropped_for(DropReason::write_failed);
        return;
    }
    ++c.forwarded;
    c.forwarded_payload_bytes += payload_bytes;
    c.forwarded_wire_bytes += wire_bits / 8;
}

void Scheduler::forward_failed(TopicId topic, std::size_t payload_bytes) {
    forward_failed(topic, payload_bytes, wire_bits(payload_bytes) / 8);
}

void Scheduler::forward_failed(TopicId topic, std::size_t payload_bytes, std::uint64_t wire_bytes) {
    TopicCounters& c = topics_[topic].counters;
    --c.forwarded;
    c.forwarded_payload_bytes -= payload_bytes;
    c.forwarded_wire_bytes -= wire_bytes;
    ++c.dropped_for(DropReason::write_failed);
}

void Scheduler::drop(Sample&& sample, DropReason reason, SampleSink& sink) {
    ++topics_[sample.topic].counters.dropped_for(reason);
    sink.drop(std::move(sample), reason);
}

void Scheduler::expire(base::SteadyTime now, SampleSink& sink) {
    if (chunked_ && chunked_->sample.deadline <= now) {
        abandon_chunks(DropReason::expired, sink);
    }
    while (!queue_.empty() && queue_.at(queue_.earliest_deadline()).deadline <= now) {
        const TopicId topic = queue_.at(queue_.earliest_deadline()).topic;
        drop(take(queue_.earliest_deadline()), topics_[topic].reachable ? DropReason::expired : DropReason::no_reader,
             sink);
    }
    for (auto it = repairs_.begin(); it != repairs_.end();) {
        const auto next = std::next(it);
        if (it->repair.deadline <= now) {
            give_up_repair(repairs_.take(it), now, sink);
        }
        it = next;
    }
}

void Scheduler::evict_over_cap(SampleSink& sink) {
    while (!queue_.empty() && queue_.memory_bytes() > config_.memory_cap_bytes) {
        drop(take(queue_.least_urgent()), DropReason::evicted, sink);
    }
}

std::optional<base::SteadyTime> Scheduler::first_yields(base::SteadyTime start) {
    if (queued_first_ == 0) {
        return std::nullopt;  // the common case, and the admit path's: no walk of the queue
    }
    std::optional<DeadlineQueue::Peek> first;
    std::optional<DeadlineQueue::Peek> urgent;
    queue_.visit_by_urgency([&](DeadlineQueue::Slot slot) {
        const DeadlineQueue::Peek peek = queue_.at(slot);
        if (!topics_[peek.topic].config.first) {
            urgent = peek;
            return false;
        }
        if (!first) {
            first = peek;
        }
        return true;
    });
    if (!first || !urgent) {
        return std::nullopt;
    }
    const TopicConfig& first_topic = topics_[first->topic].config;
    if (first_topic.yields_within <= base::Duration::zero()) {
        return std::nullopt;
    }
    std::uint64_t first_bits = 0;
    std::uint64_t urgent_bits = 0;
    std::uint64_t together_bits = 0;
    if (config_.bundles) {
        BundleBuilder bundle(config_.wire);
        first_bits = bundle.alone_wire_bits(peeked_entry(*first));
        urgent_bits = bundle.alone_wire_bits(peeked_entry(*urgent));
        bundle.add(peeked_entry(*first));
        together_bits = bundle.wire_bits(bundle.encoded_bytes_with(peeked_entry(*urgent)));
    } else {
        first_bits = wire_bits(first->payload_bytes);
        urgent_bits = wire_bits(urgent->payload_bytes);
        together_bits = first_bits + urgent_bits;
    }
    const auto arrives = [&](std::uint64_t bits) { return start + budget_.transmit_time(bits) + config_.link_latency; };
    const base::SteadyTime first_due =
        std::min(first->deadline, first->deadline - first_topic.ttl + first_topic.yields_within);
    const bool yields = arrives(together_bits) > urgent->deadline && arrives(urgent_bits) <= urgent->deadline &&
                        arrives(urgent_bits + first_bits) <= first_due;
    if (!yields) {
        return std::nullopt;
    }
    return first_due - budget_.transmit_time(first_bits);
}

bool Scheduler::may_start(DeadlineQueue::Slot slot, base::SteadyTime start, std::uint64_t bits, SampleSink& sink) {
    const DeadlineQueue::Peek sample = queue_.at(slot);
    const base::Duration tx = budget_.transmit_time(bits);
    // At a rate of 0 nothing goes, paced or not: transmit_time is Duration::max() either way.
    const bool paced = config_.paced_fragments && paces_fragments_at(budget_.rate_bps());
    const base::Duration holds_link =
        paced ? budget_.transmit_time(8u * config_.wire.first_datagram_wire_bytes(sample.payload_bytes)) : tx;
    const bool blocks_urgent = holds_link > protect_limit_for(sample.topic);
    if (start + tx + config_.link_latency > sample.deadline) {
        drop(take(slot), blocks_urgent ? DropReason::oversize : DropReason::doomed, sink);
        return false;
    }
    if (blocks_urgent) {
        // Wait for a faster link, or for the topic it would cost its deadline to go quiet (backfill's samples live
        // an hour: their give-up time wakes no one soon); give up once it could no longer make its deadline.
        base::SteadyTime wake = sample.deadline - tx - config_.link_latency + base::Duration(1);
        if (const ProtectedTopics::Guard* guard = protect_.guard_for(sample.topic, protect_rank_of(sample.topic))) {
            const TopicState& guarding = topics_[guard->topic];
            wake = std::min(wake, guarding.last_arrival + guarding.config.ttl + base::Duration(1));
        }
        blocked_wakeup_ = blocked_wakeup_ ? std::min(*blocked_wakeup_, wake) : wake;
        return false;
    }
    return true;
}

void Scheduler::release_by_deadline(base::SteadyTime now, SampleSink& sink) {
    blocked_wakeup_.reset();
    if ((queue_.empty() && !chunked_ && repairs_.empty()) || !budget_.can_send(now)) {
        return;
    }
    // The link is non-preemptive: a sample on the wire holds it for its whole wire time. Protect the most
    // urgent active topic: nothing may occupy the link longer than that topic's TTL minus its own wire time.
    protected_topics(now);
    if (config_.bundles) {
        release_bundles(now, sink);
        return;
    }

    while ((!queue_.empty() || !repairs_.empty()) && budget_.can_send(now)) {
        const base::SteadyTime start = std::max(now, budget_.busy_until());
        const bool first_waits = first_yields(start).has_value();
        bool sent = false;
        queue_.visit_by_urgency([&](DeadlineQueue::Slot slot) {
            const DeadlineQueue::Peek peek = queue_.at(slot);
            if (!repairs_.empty() &&
                send_repair_before(UrgencyKey{rank_of(peek.topic), peek.deadline}, now, start, sink)) {
                sent = true;
                return false;
            }
            if (first_waits && topics_[peek.topic].config.first) {
                return true;
            }
            const std::uint64_t bits = wire_bits(peek.payload_bytes);
            if (!may_start(slot, start, bits, sink)) {
                return true;
            }
            budget_.charge(now, bits);
            forward(take(slot), bits, sink);
            sent = true;
            return false;
        });
        if (!sent && !repairs_.empty()) {
            sent = send_repair_before(std::nullopt, now, start, sink);
        }
        if (!sent) {
            break;
        }
    }
}

void Scheduler::release_paper_period(base::SteadyTime now, SampleSink& sink) {
    const std::optional<std::vector<DeadlineQueue::Slot>> marked = paper_.run(now, queue_, sensed_rate_bps_);
    if (!marked) {
        return;
    }
    for (DeadlineQueue::Slot slot : *marked) {
        Sample sample = take(slot);
        const std::uint64_t bits = wire_bits(sample.payload.size());
        budget_.charge(now, bits);
        forward(std::move(sample), bits, sink);
    }
}

std::optional<base::SteadyTime> Scheduler::next_wakeup(base::SteadyTime now) const {
    if (queue_.empty() && !chunked_ && repairs_.empty()) {
        return idle_wakeup(now);
    }
    base::SteadyTime next = base::SteadyTime::max();
    if (!queue_.empty()) {
        next = queue_.at(queue_.earliest_deadline()).deadline;
    }
    if (const auto repair_due = repairs_.earliest_deadline()) {
        next = std::min(next, *repair_due);
    }
    if (chunked_) {
        next = std::min(next, chunked_->sample.deadline);
    }
    switch (config_.policy) {
        case PolicyKind::ttl:
        case PolicyKind::edf:
            if (budget_.rate_bps() > 0.0) {
                if (!budget_.can_send(now)) {
                    next = std::min(next, budget_.next_send_time());
                } else if (blocked_wakeup_) {
                    next = std::min(next, *blocked_wakeup_);
                }
            }
            break;
        case PolicyKind::paper:
            next = std::min(next, paper_.next_period(now));
            break;
        case PolicyKind::fifo:
            break;
    }
    return std::max(next, now);
}

void Scheduler::charge_link(base::SteadyTime now, std::uint64_t bits) {
    if (budget_.rate_bps() <= 0.0) {
        return;
    }
    bits = reserve_.uncovered(now, bits, std::max(0.0, sensed_rate_bps_ - budget_.rate_bps()));
    if (bits == 0) {
        return;
    }
    const base::SteadyTime before = budget_.busy_until();
    const base::SteadyTime after = budget_.charge(now, bits);
    const base::SteadyTime bound = std::max(before, now + config_.link_queue);
    if (after > bound) {
        budget_.release_to(bound);
    }
}

void Scheduler::observe_link_backlog(base::SteadyTime now, std::uint64_t bits) {
    if (sensed_rate_bps_ > 0.0) {
        budget_.hold_until(now + base::from_seconds(static_cast<double>(bits) / sensed_rate_bps_));
    }
}

void Scheduler::drain(SampleSink& sink, DropReason reason) {
    if (chunked_) {
        abandon_chunks(reason, sink);
    }
    while (!queue_.empty()) {
        drop(take(queue_.earliest_deadline()), reason, sink);  // parked ones too
    }
    while (!repairs_.empty()) {
        discard_repair(repairs_.take(repairs_.begin()), reason, sink);
    }
}

TopicCounters Scheduler::total_counters() const {
    TopicCounters total = retired_counters_;
    for (const TopicState& t : topics_) {
        total += t.counters;
    }
    return total;
}

}  // namespace tgw::core
