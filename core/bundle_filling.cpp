// The Scheduler in compact WAN mode: what one release step admits leaves as one bundle, and a sample too large
// for one leaves in chunks between the others (docs/design.md §8).
#include "core/scheduler.hpp"

#include <algorithm>
#include <optional>
#include <utility>

#include "compact/bundle_codec.hpp"

namespace tgw::core {

bool Scheduler::chunk_failed(std::uint32_t chunk_id, SampleSink& sink) {
    if (!chunked_ || chunked_->id != chunk_id) {
        return false;
    }
    abandon_chunks(DropReason::write_failed, sink);
    return true;
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
    if (chunked_ && start +
                            budget_.transmit_time(
                                chunk_planning_->chunk_bits(chunked_->sample.payload.size() - chunked_->sent_bytes)) +
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
                bundle.encoded_bytes() + MIN_FILLING_ROOM_BYTES <= max_bytes &&
                chunk_planning_->fits_two_bundles(peek.payload_bytes)) {
                if (!chunk_planning_->arrives_in_two_bundles(peek.deadline, start, budget_) ||
                    chunk_planning_->chunks_arrive_by(peek.payload_bytes, start, rate_left(peek.topic), budget_) >
                        peek.deadline) {
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
    if (chunk_planning_->chunks_arrive_by(peek.payload_bytes, start, rate_left_bps(rank_of(peek.topic), start),
                                          budget_) > peek.deadline) {
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

bool Scheduler::add_chunk(base::SteadyTime start, base::SteadyTime earliest_deadline, base::Duration limit,
                          BundleBuilder& bundle, std::vector<Sample>& samples) {
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
    if (lo == 0 || (lo < ChunkPlanning::MIN_CHUNK_BYTES && lo < remaining)) {
        return false;
    }
    samples.push_back(ChunkPlanning::chunk_of(whole, info, lo));
    bundle.add(entry_of(lo));
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

}  // namespace tgw::core
