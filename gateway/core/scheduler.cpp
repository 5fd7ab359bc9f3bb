#include "gateway/core/scheduler.hpp"

#include <algorithm>
#include <optional>
#include <utility>

#include "gateway/compact/bundle_codec.hpp"

namespace tgw::core {

namespace {

/// A queued sample as a bundle entry, to size it without taking it from the queue.
BundleBuilder::Entry peeked_entry(const DeadlineQueue::Peek& peek) {
    return BundleBuilder::Entry::of(peek.topic, peek.route, peek.source_time, *peek.payload, peek.keyed);
}

}  // namespace

void Scheduler::ProtectedTopics::offer(const Guard& guard) {
    if (guard.limit <= base::Duration::zero()) {
        return;  // no other sample's wait could let it arrive in time
    }
    if (guard.limit < first.limit) {
        second = first;
        first = guard;
    } else if (guard.limit < second.limit) {
        second = guard;
    }
}

bool Scheduler::ProtectedTopics::update(const Guard& guard) {
    if (guard.limit <= base::Duration::zero()) {
        return guard.topic != first.topic && guard.topic != second.topic;  // one leaves: the next is unknown
    }
    if (guard.topic == first.topic) {
        if (guard.limit > second.limit)
            return false;  // the new second is unknown
        first = guard;
    } else if (guard.topic == second.topic) {
        if (guard.limit < first.limit) {
            second = first;
            first = guard;
        } else if (guard.limit <= second.limit) {
            second = guard;
        } else {
            return false;
        }
    } else {
        offer(guard);
    }
    return true;
}

Scheduler::Scheduler(const SchedulerConfig& config)
    : config_(config),
      sensed_rate_bps_(config.initial_rate_bps),
      budget_(config.initial_rate_bps * config.budget_fraction, config.lead) {}

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

const Scheduler::ProtectedTopics& Scheduler::protected_topics(base::SteadyTime now) {
    // Only a push (handled there), a TTL or a rate change can bring a topic in; the two fall out by going
    // inactive. Time running backwards could make topics active again.
    const bool still_valid = protect_valid_ && now >= protect_built_at_ &&
                             (protect_.first.topic == ProtectedTopics::NONE || active(protect_.first.topic, now)) &&
                             (protect_.second.topic == ProtectedTopics::NONE || active(protect_.second.topic, now));
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

void Scheduler::push_repair(const Repair& repair, base::SteadyTime now, SampleSink& sink) {
    switch (repair.kind) {
        case Repair::Kind::repair:
            ++repair_counters_.received;
            break;
        case Repair::Kind::continuation:
            ++repair_counters_.continuations_received;
            break;
        case Repair::Kind::announcement:
        case Repair::Kind::writer_announcement:
            break;
    }
    switch (config_.policy) {
        case PolicyKind::fifo:
            send_repair_now(repair, sink);
            return;
        case PolicyKind::paper:
            charge_link(now, repair.wire_bits - std::min(repair.prepaid_bits, repair.wire_bits));
            send_repair_now(repair, sink);
            return;
        case PolicyKind::ttl:
        case PolicyKind::edf:
            break;
    }
    if (repair.kind == Repair::Kind::continuation) {
        budget_.refund(repair.prepaid_bits);  // charged again as it leaves
        if (cut_short(repair)) {
            discard_repair(repair, DropReason::doomed, sink);
            return;
        }
    }
    Repair held = repair;
    if (repair.kind == Repair::Kind::writer_announcement) {
        // Before every sample of its topic: a base camp drops a sample of a writer it has not heard of. A writer
        // made anew (the WAN participant on a new address) finds its topic's samples queued.
        if (const std::optional<base::SteadyTime> first = queue_.earliest_deadline_of(repair.topic)) {
            held.deadline = std::min(held.deadline, *first - base::Duration(1));
        }
    }
    if (held.deadline <= now + config_.link_latency) {
        give_up_repair(held, now, sink);
        return;
    }
    repairs_.push(held, rank_of(held));
    if (repairs_.size() > MAX_QUEUED_REPAIRS) {
        discard_repair(repairs_.take(repairs_.least_urgent()), DropReason::evicted, sink);
    }
}

bool Scheduler::send_repair_before(const std::optional<UrgencyKey>& bound, base::SteadyTime now, base::SteadyTime start,
                                   SampleSink& sink) {
    for (auto it = repairs_.begin(); it != repairs_.end();) {
        const RepairQueue::Entry& entry = *it;
        if (bound &&
            (entry.rank > bound->rank || (entry.rank == bound->rank && entry.repair.deadline >= bound->deadline))) {
            return false;
        }
        const base::Duration tx = budget_.transmit_time(entry.repair.wire_bits);
        const auto next = std::next(it);
        if (cut_short(entry.repair)) {
            discard_repair(repairs_.take(it), DropReason::doomed, sink);
            it = next;
            continue;
        }
        if (start + tx + config_.link_latency > entry.repair.deadline) {
            give_up_repair(repairs_.take(it), now, sink);
            it = next;
            continue;
        }
        if (tx > protect_limit_for(entry.repair)) {
            // As a sample held back by the non-preemptive rule: looked at again when it must go or give up.
            const base::SteadyTime give_up = entry.repair.deadline - tx - config_.link_latency + base::Duration(1);
            blocked_wakeup_ = blocked_wakeup_ ? std::min(*blocked_wakeup_, give_up) : give_up;
            it = next;
            continue;
        }
        const Repair repair = repairs_.take(it);
        budget_.charge(now, repair.wire_bits);
        send_repair_now(repair, sink);
        return true;
    }
    return false;
}

bool Scheduler::send_announcement_in_slack(base::SteadyTime now, base::SteadyTime start, SampleSink& sink) {
    const auto it = std::find_if(repairs_.begin(), repairs_.end(), [](const RepairQueue::Entry& entry) {
        return entry.repair.kind == Repair::Kind::announcement;
    });
    if (it == repairs_.end()) {
        return false;
    }
    const base::Duration tx = budget_.transmit_time(it->repair.wire_bits);
    if (tx > protect_limit_for(it->repair)) {
        return false;
    }
    const BundleBuilder alone(config_.wire);
    const auto still_in_time = [&](DeadlineQueue::Slot slot) {
        const DeadlineQueue::Peek peek = queue_.at(slot);
        return start + tx + budget_.transmit_time(alone.alone_wire_bits(peeked_entry(peek))) + config_.link_latency <=
               peek.deadline;
    };
    // Each sample more urgent than it, most urgent first (a few: what the link has not carried yet of the hazards
    // and the state); the less urgent are no concern of the announcement's, as in its rank.
    constexpr std::size_t MAX_LOOKED_AT = 16;
    const std::int64_t rank = rank_of(it->repair);
    bool in_time = true;
    std::size_t looked_at = 0;
    queue_.visit_by_urgency([&](DeadlineQueue::Slot slot) {
        if (rank_of(queue_.at(slot).topic) >= rank || ++looked_at > MAX_LOOKED_AT) {
            return false;
        }
        in_time = still_in_time(slot);
        return in_time;
    });
    if (!in_time) {
        return false;
    }
    const Repair announcement = repairs_.take(it);
    budget_.charge(now, announcement.wire_bits);
    send_repair_now(announcement, sink);
    return true;
}

RepairCounters Scheduler::repair_counters() const {
    RepairCounters counters = repair_counters_;
    counters.queued = repairs_.size();
    return counters;
}

void Scheduler::send_repair_now(const Repair& repair, SampleSink& sink) {
    switch (repair.kind) {
        case Repair::Kind::repair:
            ++repair_counters_.sent;
            repair_counters_.sent_wire_bytes += repair.wire_bits / 8;
            break;
        case Repair::Kind::announcement:
            ++repair_counters_.announcements_sent;
            repair_counters_.announcements_sent_wire_bytes += repair.wire_bits / 8;
            break;
        case Repair::Kind::continuation:
            ++repair_counters_.continuations_sent;
            repair_counters_.continuations_sent_wire_bytes += repair.wire_bits / 8;
            break;
        case Repair::Kind::writer_announcement:
            ++repair_counters_.writer_announcements_sent;
            repair_counters_.writer_announcements_sent_wire_bytes += repair.wire_bits / 8;
            break;
    }
    sink.send_repair(repair.id);
}

void Scheduler::give_up_repair(const Repair& repair, base::SteadyTime now, SampleSink& sink) {
    if (repair.kind == Repair::Kind::writer_announcement) {
        ++repair_counters_.writer_announcements_late;  // a base camp must hear of the writer, late or not
        charge_link(now, repair.wire_bits);
        send_repair_now(repair, sink);
        return;
    }
    if (repair.kind != Repair::Kind::announcement) {
        discard_repair(repair, DropReason::doomed, sink);
        return;
    }
    // Not while the link is down (a rate of 0): there it goes as before, and a camp that lost the robot hears it.
    if (repair.skippable && budget_.rate_bps() > 0.0 &&
        budget_.transmit_time(repair.wire_bits) > protect_limit_for(repair)) {
        ++repair_counters_.announcements_skipped;
        sink.discard_repair(repair.id);
        return;
    }
    ++repair_counters_.announcements_late;
    charge_link(now, repair.wire_bits);
    send_repair_now(repair, sink);
}

void Scheduler::discard_repair(const Repair& repair, DropReason reason, SampleSink& sink) {
    if (repair.kind == Repair::Kind::continuation) {
        ++repair_counters_.continuations_late;
    } else {
        ++(reason == DropReason::doomed ? repair_counters_.late : repair_counters_.discarded);
    }
    sink.discard_repair(repair.id);
    if (repair.kind == Repair::Kind::continuation && repair.sample != 0 && !cut_short(repair)) {
        note_cut_short(repair, reason);
        sink.sample_cut_short(repair.sample, reason);
    }
}

bool Scheduler::cut_short(const Repair& repair) const {
    return repair.kind == Repair::Kind::continuation && repair.sample != 0 &&
           std::find(cut_short_.begin(), cut_short_.end(), repair.sample) != cut_short_.end();
}

void Scheduler::note_cut_short(const Repair& continuation, DropReason reason) {
    // A sample's continuations come in one after another: the last few samples cut are enough to know.
    cut_short_[next_cut_short_++ % cut_short_.size()] = continuation.sample;
    ++repair_counters_.samples_cut_short;
    if (continuation.topic >= topics_.size()) {
        return;
    }
    // Counted forwarded when its write was decided: it did not arrive, and the sink keeps it with the reason.
    TopicCounters& c = topics_[continuation.topic].counters;
    if (c.forwarded > 0) {
        --c.forwarded;
        c.forwarded_payload_bytes -=
            std::min<std::uint64_t>(c.forwarded_payload_bytes, continuation.sample_payload_bytes);
    }
    ++c.dropped_for(reason);
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

bool Scheduler::chunk_failed(std::uint32_t chunk_id, SampleSink& sink) {
    if (!chunked_ || chunked_->id != chunk_id) {
        return false;
    }
    abandon_chunks(DropReason::write_failed, sink);
    return true;
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

void Scheduler::release_bundles(base::SteadyTime now, SampleSink& sink) {
    BundleBuilder bundle(config_.wire);
    while ((!queue_.empty() || chunked_ || !repairs_.empty()) && budget_.can_send(now)) {
        const base::SteadyTime start = std::max(now, budget_.busy_until());
        if (!repairs_.empty()) {
            std::optional<UrgencyKey> most_urgent;
            queue_.visit_by_urgency([&](DeadlineQueue::Slot slot) {
                const DeadlineQueue::Peek peek = queue_.at(slot);
                most_urgent = UrgencyKey{rank_of(peek.topic), peek.deadline};
                return false;
            });
            if (send_repair_before(most_urgent, now, start, sink) || send_announcement_in_slack(now, start, sink)) {
                continue;
            }
        }
        bundle.clear();
        std::vector<Sample> samples = fill_bundle(start, bundle, sink);
        if (samples.empty()) {
            if (!repairs_.empty() && send_repair_before(std::nullopt, now, start, sink)) {
                continue;
            }
            break;
        }
        const std::uint64_t most_bits = bundle.wire_bits(bundle.encoded_bytes());
        struct Tally {
            TopicId topic;
            std::size_t payload_bytes;
            bool chunk;
        };
        std::vector<Tally> tallies;
        tallies.reserve(samples.size());
        std::size_t payload_bytes = 0;
        bool has_chunk = false;
        for (const Sample& s : samples) {
            tallies.push_back({s.topic, s.payload.size(), s.chunk.has_value()});
            payload_bytes += s.payload.size();
            has_chunk = has_chunk || s.chunk.has_value();
        }
        const std::uint64_t bits =
            8u * sink.forward_bundle(std::move(samples), static_cast<std::size_t>(most_bits / 8));
        const bool written = bits > 0;
        budget_.charge(now, written ? bits : most_bits);
        BundleShares shares(bits / 8, payload_bytes, tallies.size());
        for (const Tally& t : tallies) {
            TopicCounters& c = topics_[t.topic].counters;
            const std::uint64_t share = shares.next(t.payload_bytes);
            if (written) {
                topics_[t.topic].link_use.add(now, 8.0 * static_cast<double>(share));
            }
            if (t.chunk) {
                c.forwarded_wire_bytes += written ? share : 0;  // the sample counts once, below
                continue;
            }
            if (!written) {
                ++c.dropped_for(DropReason::write_failed);
                continue;
            }
            ++c.forwarded;
            c.forwarded_payload_bytes += t.payload_bytes;
            c.forwarded_wire_bytes += share;
        }
        if (has_chunk && !written) {
            abandon_chunks(DropReason::write_failed, sink);
        } else if (chunked_ && chunked_->sent_bytes == chunked_->sample.payload.size()) {
            // Its last chunk has left: the sample is forwarded.
            TopicCounters& c = topics_[chunked_->sample.topic].counters;
            --c.queued;
            c.queued_payload_bytes -= chunked_->sample.payload.size();
            ++c.forwarded;
            c.forwarded_payload_bytes += chunked_->sample.payload.size();
            sink.chunked_sample_left(std::move(chunked_->sample));
            chunked_.reset();
        }
    }
}

std::vector<Sample> Scheduler::fill_bundle(base::SteadyTime start, BundleBuilder& bundle, SampleSink& sink) {
    // Smaller, less urgent samples may fill the room a larger one left; looking further costs time for little.
    constexpr std::size_t MAX_CANDIDATES = 64;
    // A sample at least this large that does not fit the room left fills it with its first chunk, if the room is
    // at least this large: smaller ones wait for a bundle of their own rather than pay a chunk's header twice.
    constexpr std::size_t MIN_FILLING_SAMPLE_BYTES = 512;
    constexpr std::size_t MIN_FILLING_ROOM_BYTES = 256;
    std::vector<Sample> samples;
    const std::size_t max_bytes = config_.bundles->max_encoded_bytes;
    base::SteadyTime earliest_deadline = base::SteadyTime::max();
    base::Duration limit = base::Duration::max();  // the non-preemptive rule's, for what the bundle holds
    std::size_t candidates = 0;
    bool chunk_tried = false;
    bool passed_over = false;  // a more urgent sample waits for a later bundle
    // The rate the more urgent topics leave, summed over all topics: once per rank and bundle.
    std::optional<std::pair<std::int64_t, double>> rate_left_of_rank;
    const auto rate_left = [&](TopicId topic) {
        const std::int64_t rank = rank_of(topic);
        if (!rate_left_of_rank || rate_left_of_rank->first != rank) {
            rate_left_of_rank.emplace(rank, rate_left_bps(rank, start));
        }
        return rate_left_of_rank->second;
    };
    if (chunked_ && start + budget_.transmit_time(chunk_bits(chunked_->sample.payload.size() - chunked_->sent_bytes)) +
                            config_.link_latency >
                        chunked_->sample.deadline) {
        abandon_chunks(DropReason::doomed, sink);  // what is left can no longer arrive in time
    }
    // The chunked sample's next chunk goes where the sample would stand in the queue.
    const auto try_chunk = [&] {
        chunk_tried = true;
        if (!chunked_) {
            return;
        }
        const bool alone = bundle.empty();
        if (add_chunk(start, earliest_deadline, limit, bundle, samples)) {
            limit = std::min(limit, protect_limit_for(chunked_->sample.topic));
            earliest_deadline = std::min(earliest_deadline, chunked_->sample.deadline);
        } else if (alone) {
            // Not even a small chunk is short enough for the most urgent topic: look again once it goes quiet.
            const ProtectedTopics::Guard* guard =
                protect_.guard_for(chunked_->sample.topic, protect_rank_of(chunked_->sample.topic));
            if (guard != nullptr) {
                const TopicState& t = topics_[guard->topic];
                const base::SteadyTime quiet = t.last_arrival + t.config.ttl + base::Duration(1);
                blocked_wakeup_ = blocked_wakeup_ ? std::min(*blocked_wakeup_, quiet) : quiet;
            }
        }
    };
    // A status that yields this bundle leaves in the next: this one must leave it the time.
    const std::optional<base::SteadyTime> first_waits = first_yields(start);
    if (first_waits) {
        earliest_deadline = *first_waits;
    }
    queue_.visit_by_urgency([&](DeadlineQueue::Slot slot) {
        const DeadlineQueue::Peek peek = queue_.at(slot);
        if (first_waits && topics_[peek.topic].config.first) {
            passed_over = true;
            return true;
        }
        if (chunked_ && !chunk_tried) {
            const std::int64_t rank = rank_of(peek.topic);
            if (chunked_->rank < rank || (chunked_->rank == rank && chunked_->sample.deadline <= peek.deadline)) {
                try_chunk();
            }
        }
        const auto entry = peeked_entry(peek);
        if (bundle.empty()) {
            const std::uint64_t alone_bits = bundle.alone_wire_bits(entry);
            const bool too_large = bundle.encoded_bytes_with(entry) > max_bytes ||
                                   budget_.transmit_time(alone_bits) > protect_limit_for(peek.topic);
            if (too_large) {
                // In chunks, urgent samples travel between them; one sample at a time, the others wait. A bundle
                // is never fragmented.
                if (!chunked_ && start_chunks(slot, start, sink)) {
                    try_chunk();
                } else {
                    passed_over = true;
                }
                return true;
            }
            // The first goes as a sample alone would.
            if (!may_start(slot, start, alone_bits, sink)) {
                passed_over = true;
                return true;
            }
        } else {
            if (++candidates > MAX_CANDIDATES) {
                return false;
            }
            const std::size_t bytes = bundle.encoded_bytes_with(entry);
            if (bytes > max_bytes && !chunked_ && peek.payload_bytes >= MIN_FILLING_SAMPLE_BYTES &&
                bundle.encoded_bytes() + MIN_FILLING_ROOM_BYTES <= max_bytes && fits_two_bundles(peek)) {
                if (!arrives_in_two_bundles(peek, start) ||
                    chunks_arrive_by(peek.payload_bytes, start, rate_left(peek.topic)) > peek.deadline) {
                    // Filled in, it would arrive late, and it goes whole only when nothing more urgent waits. Not
                    // passed over: while the oldest of a starved topic sits here until it expires, a younger one
                    // of the same topic that can still arrive takes the room.
                    return true;
                }
                if (!passed_over) {
                    // A large sample fills the room left in chunks: the bundle leaves full, its headers paid once.
                    // Only when nothing more urgent waits: the room it takes delays the next bundle.
                    if (start_chunks(slot, start, sink)) {
                        try_chunk();
                    }
                    return bundle.encoded_bytes() < max_bytes;
                }
            }
            const base::Duration tx = budget_.transmit_time(bundle.wire_bits(bytes));
            // Joining must cost no entry its deadline, nor the most urgent topic its own (docs/design.md §4).
            if (bytes > max_bytes || start + tx + config_.link_latency > std::min(earliest_deadline, peek.deadline) ||
                tx > std::min(limit, protect_limit_for(peek.topic))) {
                passed_over = true;
                return true;
            }
        }
        limit = std::min(limit, protect_limit_for(peek.topic));
        earliest_deadline = std::min(earliest_deadline, peek.deadline);
        bundle.add(entry);
        samples.push_back(take(slot));
        return bundle.encoded_bytes() < max_bytes;
    });
    if (chunked_ && !chunk_tried) {
        try_chunk();
    }
    return samples;
}

bool Scheduler::start_chunks(DeadlineQueue::Slot slot, base::SteadyTime start, SampleSink& sink) {
    const DeadlineQueue::Peek peek = queue_.at(slot);
    if (chunks_arrive_by(peek.payload_bytes, start, rate_left_bps(rank_of(peek.topic), start)) > peek.deadline) {
        drop(take(slot), DropReason::doomed, sink);
        return false;
    }
    ChunkedSample chunked;
    chunked.rank = rank_of(peek.topic);
    chunked.sample = take(slot);
    // Still queued, as far as the counters go, until its last chunk has left.
    TopicCounters& c = topics_[chunked.sample.topic].counters;
    ++c.queued;
    c.queued_payload_bytes += chunked.sample.payload.size();
    chunked.id = ++next_chunk_id_;
    chunked_ = std::move(chunked);
    return true;
}

bool Scheduler::fits_two_bundles(const DeadlineQueue::Peek& sample) const {
    const std::size_t room = config_.bundles->max_encoded_bytes - compact::BundleCodec::MAX_FRAME_BYTES;
    return sample.payload_bytes <= 2 * room;
}

bool Scheduler::arrives_in_two_bundles(const DeadlineQueue::Peek& sample, base::SteadyTime start) const {
    // Its rest goes in the next bundle, and both bundles full must leave before its deadline: a sample that only
    // gets the room others leave must not be started to be abandoned, its chunks sent for nothing.
    const std::uint64_t two_full = 2 * BundleBuilder(config_.wire).wire_bits(config_.bundles->max_encoded_bytes);
    return start + budget_.transmit_time(two_full) + config_.link_latency <= sample.deadline;
}

double Scheduler::rate_left_bps(std::int64_t rank, base::SteadyTime at) const {
    // What the more urgent topics took of the link lately they will take while a sample of `rank` is on its way.
    double rate_bps = budget_.rate_bps();
    for (TopicId t = 0; t < topics_.size(); ++t) {
        if (rank_of(t) < rank) {
            rate_bps -= topics_[t].link_use.per_second(at);
        }
    }
    return rate_bps;
}

base::SteadyTime Scheduler::chunks_arrive_by(std::size_t payload_bytes, base::SteadyTime start, double rate_bps) const {
    // What the more urgent topics leave varies from bundle to bundle (a status, a burst of C), and a sample
    // abandoned halfway wastes every chunk it sent: plan on a part of the rate they left lately. On the testbed at
    // 25,000 bit/s (the paper's workload, 60 s) 4 of 28 chunked samples were abandoned when planned on 0.8 of it,
    // 1 of 27 on 0.6; a starved topic loses nothing by it, a younger sample of it takes the room.
    constexpr double RATE_LEFT_MARGIN = 0.6;
    rate_bps *= RATE_LEFT_MARGIN;
    if (rate_bps <= 0.0) {
        return base::SteadyTime::max();
    }
    // Its last chunk arrives with the bundle it is in: at worst a full one that starts once the rest has gone.
    const std::uint64_t last_bundle = BundleBuilder(config_.wire).wire_bits(config_.bundles->max_encoded_bytes);
    return start + base::from_seconds(static_cast<double>(chunk_bits(payload_bytes)) / rate_bps) +
           budget_.transmit_time(last_bundle) + config_.link_latency;
}

std::uint64_t Scheduler::chunk_bits(std::size_t payload_bytes) const {
    // At best the whole link is the sample's: a chunk per bundle, each bundle's headers on top of the payload.
    const std::size_t room = config_.bundles->max_encoded_bytes - compact::BundleCodec::MAX_FRAME_BYTES;
    const std::size_t chunks = (payload_bytes + room - 1) / std::max<std::size_t>(room, 1);
    return 8u * payload_bytes + chunks * BundleBuilder(config_.wire).wire_bits(compact::BundleCodec::MAX_FRAME_BYTES);
}

bool Scheduler::add_chunk(base::SteadyTime start, base::SteadyTime earliest_deadline, base::Duration limit,
                          BundleBuilder& bundle, std::vector<Sample>& samples) {
    // A chunk smaller than this is not worth its entry's header.
    constexpr std::size_t MIN_CHUNK_BYTES = 64;
    ChunkedSample& c = *chunked_;
    const Sample& whole = c.sample;
    const std::size_t remaining = whole.payload.size() - c.sent_bytes;
    if (remaining == 0) {
        return false;
    }
    const Sample::Chunk info{c.id, static_cast<std::uint32_t>(whole.payload.size()),
                             static_cast<std::uint32_t>(c.sent_bytes)};
    const bool plain = c.sent_bytes == 0 && compact::BundleCodec::plain_cdr(whole.payload.data(), whole.payload.size());
    const auto entry_of = [&](std::size_t n) {
        return BundleBuilder::Entry{whole.topic,     whole.route, whole.source_time, n, plain && n >= 4,
                                    whole.key.valid, &info};
    };
    const base::Duration own_limit = std::min(limit, protect_limit_for(whole.topic));
    const base::SteadyTime by = std::min(earliest_deadline, whole.deadline);
    const auto fits = [&](std::size_t n) {
        const std::size_t bytes = bundle.encoded_bytes_with(entry_of(n));
        const base::Duration tx = budget_.transmit_time(bundle.wire_bits(bytes));
        return bytes <= config_.bundles->max_encoded_bytes && start + tx + config_.link_latency <= by &&
               tx <= own_limit;
    };
    // The largest chunk that fits: the sizes that fit are those below a bound.
    std::size_t lo = 0, hi = remaining;
    while (lo < hi) {
        const std::size_t mid = lo + (hi - lo + 1) / 2;
        if (fits(mid)) {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    if (lo == 0 || (lo < MIN_CHUNK_BYTES && lo < remaining)) {
        return false;
    }
    Sample chunk;
    chunk.topic = whole.topic;
    chunk.route = whole.route;
    chunk.kind = whole.kind;
    chunk.key = whole.key;
    chunk.source_time = whole.source_time;
    chunk.arrival = whole.arrival;
    chunk.deadline = whole.deadline;
    chunk.sequence = whole.sequence;
    chunk.chunk = info;
    const auto from = whole.payload.begin() + static_cast<std::ptrdiff_t>(c.sent_bytes);
    chunk.payload.assign(from, from + static_cast<std::ptrdiff_t>(lo));
    bundle.add(entry_of(lo));
    samples.push_back(std::move(chunk));
    c.sent_bytes += lo;
    return true;
}

void Scheduler::abandon_chunks(DropReason reason, SampleSink& sink) {
    Sample sample = std::move(chunked_->sample);
    chunked_.reset();
    TopicCounters& c = topics_[sample.topic].counters;
    --c.queued;
    c.queued_payload_bytes -= sample.payload.size();
    drop(std::move(sample), reason, sink);
}

void Scheduler::release_paper_period(base::SteadyTime now, SampleSink& sink) {
    if (!paper_started_) {
        next_paper_period_ = now;
        paper_started_ = true;
    }
    if (now < next_paper_period_) {
        return;
    }
    // The paper's filter: walk the list by TTL and mark what fits in rate x period, counting only payload
    // (plus an assumed overhead factor); send the marked at once. The rest waits for the next period.
    // The paper spends the whole sensed rate; its only margin is the assumed overhead.
    double remaining_bits = sensed_rate_bps_ * base::to_seconds(config_.paper_period);
    std::vector<DeadlineQueue::Slot> marked;
    queue_.visit_by_urgency([&](DeadlineQueue::Slot slot) {
        const double bits = 8.0 * static_cast<double>(queue_.at(slot).payload_bytes) * (1.0 + config_.paper_overhead);
        if (bits <= remaining_bits) {
            remaining_bits -= bits;
            marked.push_back(slot);
        }
        return true;
    });
    for (DeadlineQueue::Slot slot : marked) {
        Sample sample = take(slot);
        const std::uint64_t bits = wire_bits(sample.payload.size());
        budget_.charge(now, bits);
        forward(std::move(sample), bits, sink);
    }
    next_paper_period_ += config_.paper_period;
    if (next_paper_period_ <= now) {
        next_paper_period_ = now + config_.paper_period;
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
            next = std::min(next, paper_started_ ? next_paper_period_ : now);
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
    const double reserve_bps = std::max(0.0, sensed_rate_bps_ - budget_.rate_bps());
    if (now > reserve_time_) {
        reserve_bits_ = std::min(reserve_bits_ + reserve_bps * base::to_seconds(now - reserve_time_),
                                 reserve_bps * base::to_seconds(config_.reserve_window));
        reserve_time_ = now;
    }
    const double covered = std::min(reserve_bits_, static_cast<double>(bits));
    reserve_bits_ -= covered;
    bits -= static_cast<std::uint64_t>(covered);
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
