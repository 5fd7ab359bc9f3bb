// The Scheduler's repairs: what the WAN participant sends beside the samples (repairs, the fragments it holds
// back, announcements) goes in the order of urgency of the sample it belongs to (docs/design.md §4).
#include "core/scheduler.hpp"

#include <algorithm>
#include <optional>
#include <utility>

namespace tgw::core {

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

}  // namespace tgw::core
