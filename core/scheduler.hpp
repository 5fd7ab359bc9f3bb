#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/bundle_builder.hpp"
#include "core/chunk_planning.hpp"
#include "core/deadline_queue.hpp"
#include "core/decaying_rate.hpp"
#include "core/idle_source.hpp"
#include "core/latest_samples.hpp"
#include "core/link_budget.hpp"
#include "core/link_reserve.hpp"
#include "core/paper_filter.hpp"
#include "core/policy_kind.hpp"
#include "core/protected_topics.hpp"
#include "core/rate_cap.hpp"
#include "core/repair_queue.hpp"
#include "core/sample_sink.hpp"
#include "core/topic_counters.hpp"
#include "core/wire_model.hpp"

namespace tgw::core {

struct SchedulerConfig {
    PolicyKind policy = PolicyKind::ttl;
    double initial_rate_bps = 0.0;
    /// The share of the sensed rate the budget spends. The rest absorbs what the gateway does not schedule (the
    /// WAN participant's discovery traffic, charge_link) and a sensor that reads a little high, so that the
    /// shaper's queue drains instead of standing full.
    double budget_fraction = 0.95;
    /// The default in compact WAN mode: the budget there charges each bundle at the bytes the writer put on the
    /// wire rather than at a model of them, so less is kept back (measured on the testbed: 0.98 against 0.95, 2 to
    /// 3 points more on-time payload at 25,000 and 40,000 bit/s; 0.99 against 0.98, 0.8 more at 20,000 and 40,000,
    /// nothing lost on the link). What the rest does not cover of the traffic outside the schedule is charged.
    static constexpr double COMPACT_BUDGET_FRACTION = 0.99;
    /// How long the unspent rest of the rate is saved up for traffic charged from outside (charge_link): a
    /// participant announcing itself every 20 s fits in it, a burst beyond it holds the budget.
    base::Duration reserve_window = std::chrono::seconds(20);
    WireModel wire;
    /// Compact WAN mode (`ttl` and `edf` only): what one release step admits leaves as one bundle of at most these
    /// limits, charged as the one DDS sample it is; nullopt: each sample is a DDS sample of its own (standard).
    std::optional<BundleLimits> bundles;
    /// Standard WAN mode: up to CONTINUATION_PACING_MAX_BPS the WAN transport holds a large sample's fragments after
    /// its first for the schedule (Repair::Kind::continuation). A sample then holds the link for its first datagram
    /// only, and the non-preemptive rule weighs that, not its whole wire time.
    bool paced_fragments = false;
    std::size_t memory_cap_bytes = 64u << 20;
    /// How early the next sample may be handed to the link before the previous one has drained.
    base::Duration lead = std::chrono::milliseconds(2);
    /// One-way latency of the link beyond transmission, counted when judging whether a sample can still arrive.
    base::Duration link_latency = base::Duration::zero();
    /// The longest a link queue holds (its depth in time at the sensed rate). Traffic the gateway does not
    /// schedule may come in bursts larger than that (discovery at start-up); what overflows the queue is
    /// dropped on the way, not delayed, so charge_link holds the budget no further than this ahead.
    base::Duration link_queue = std::chrono::seconds(1);
    /// Deadlines from the publisher's source timestamp (true) or from the arrival at the gateway (false).
    bool trust_source_clock = true;
    /// `paper` only: the filter's period, and the overhead it assumes on top of the payload (0.25 = 25 %).
    base::Duration paper_period = std::chrono::seconds(1);
    double paper_overhead = 0.0;
};

/// The per-topic facts the scheduler needs.
struct TopicConfig {
    std::string name;
    base::Duration ttl = std::chrono::seconds(5);
    /// Ordered before every other topic, whatever the policy and the TTLs (its TTL still sets its deadline): the
    /// gateway's status under --channel-grants, whose grants follow what the status tells; behind a backlog of
    /// samples of its own TTL it would expire, and the base camp would never hear the demand.
    bool first = false;
    /// A `first` topic's sample yields to the most urgent other sample where that one would miss its deadline
    /// behind it, and makes it going before, while it still arrives within this of its birth itself; 0: never.
    /// At a share of 10,000 bit/s a status is half a second of wire, and A samples due sooner expired behind it,
    /// three at a time. The gateway's status yields within its Lifespan: bounded to 1 s (its TTL without grants),
    /// it arrived too old to yield just when its bytes cost the most (three robots: A 193 to 200 of 200 on time,
    /// against 199 to 200 yielding within 5 s).
    base::Duration yields_within = base::Duration::zero();
    /// At most this many of its samples a second are taken in (RateCap); the rest go to the log as
    /// DropReason::rate_capped. 0: no cap.
    double max_rate_hz = 0.0;
    /// A newer data sample of an instance (the topic, for an unkeyed one) replaces the one still queued, which goes
    /// to the log as DropReason::superseded: a state topic (pose, battery) sends its latest value, not a backlog.
    bool latest_only = false;
};

/// The scheduling core: a pure step machine with no clock and no threads of its own. Samples come in with
/// push(); release(now) sends what the policy and the link budget admit, and logs what can no longer be
/// sent; next_wakeup() says when release() has something to do again. Not thread-safe: ForwardingLoop wraps
/// it for the gateway, tm-sim drives it in simulated time.
class Scheduler {
  public:
    explicit Scheduler(const SchedulerConfig& config);

    /// A new topic, in the slot of a retired one where retire_topic() allowed it (the per-topic tables do not grow
    /// with topics that come and go), else in a new slot.
    TopicId add_topic(const TopicConfig& topic);
    /// A new topic in `slot`, which must be a retired one's (compact WAN mode gives a topic that comes back the id
    /// its catalog entry already names). Any slot retired, reusable by anyone or not, may be taken. False, changing
    /// nothing, when `slot` is not a retired one.
    bool add_topic_at(TopicId slot, const TopicConfig& topic);
    /// Forgets a topic that has nothing queued: its counts leave its slot for retired_counters() (total_counters()
    /// keeps them), and the slot is free for add_topic() when `reusable`, else only for add_topic_at(). Returns
    /// the topic's final counts; nullopt, changing nothing, while samples of it are queued or when it is retired.
    std::optional<TopicCounters> retire_topic(TopicId topic, bool reusable);
    /// Whether `topic` is a slot retire_topic() emptied and no topic took again.
    bool retired(TopicId topic) const { return topics_[topic].retired; }
    void set_ttl(TopicId topic, base::Duration ttl);
    const TopicConfig& topic(TopicId id) const { return topics_[id].config; }
    /// Slots, retired ones included: every TopicId is below this.
    std::size_t topic_count() const { return topics_.size(); }
    /// Topics not retired.
    std::size_t live_topics() const { return topics_.size() - retired_slots_; }

    /// Take a sample in. `now` and `wall_now` are the same instant on the two clocks. Samples already
    /// expired, and the least urgent when over the memory cap, go to `sink.drop`; under `fifo` the sample is
    /// forwarded at once.
    void push(Sample&& sample, base::SteadyTime now, base::WallTime wall_now, SampleSink& sink);

    /// One scheduling step at `now`.
    void release(base::SteadyTime now, SampleSink& sink);

    /// Take a repair in (see Repair): it goes in the order of urgency of the sample it repairs, when the budget
    /// admits its wire bits, and only while it can still arrive before that sample's deadline; else it goes to
    /// `sink.discard_repair`. Under `fifo` and `paper`, which keep no order on the link, it is sent at once (`paper`
    /// charges it as traffic from outside). Repairs never count as samples received or forwarded.
    void push_repair(const Repair& repair, base::SteadyTime now, SampleSink& sink);
    RepairCounters repair_counters() const;
    /// A repair that will not be sent (one given after drain(), or the least urgent when too many wait): `reason`
    /// says why (doomed: it could no longer arrive in time). The first continuation of a sample not sent cuts the
    /// sample short, which then counts as dropped for `reason`; the sink keeps it.
    void discard_repair(const Repair& repair, DropReason reason, SampleSink& sink);
    /// At most this many repairs wait; past it, the least urgent is discarded.
    static constexpr std::size_t MAX_QUEUED_REPAIRS = 4096;

    /// Work for the link when no live sample wants it (backfill, under `ttl` and `edf`): samples of `topic` (the
    /// least urgent of all by its TTL) that `source` hands out, one at a time, asked for by release() only when
    /// nothing is queued, no repair waits, the link is free now and the topic is reachable. Each then goes as any
    /// sample of its topic: by the budget and the non-preemptive rule, in chunks in compact mode; its fate reaches
    /// the sink as any sample's. nullptr: none.
    void set_idle_source(IdleSource* source, TopicId topic);

    /// When release() has something to do next, absent new samples or rate changes; nullopt if nothing.
    std::optional<base::SteadyTime> next_wakeup(base::SteadyTime now) const;

    /// Whether anyone at the other end of the link takes the topic (a base-camp reader matched with its WAN
    /// writer). An unreachable topic's samples stay queued, not sent, until it is reachable again or their
    /// deadline passes; then they go to `sink.drop` as no_reader. Topics start reachable.
    void set_reachable(TopicId topic, bool reachable);
    bool reachable(TopicId topic) const { return topics_[topic].reachable; }

    /// Follow a new reading of the rate sensor. `steady_outside_bps` of the rate goes to traffic charged from
    /// outside at a steady rate (the base camp's commands on a half-duplex link): the budget spends the rest, at
    /// least MIN_SCHEDULED_SHARE of what it would, and that traffic's charges fall to the reserve it leaves. Charged
    /// against the whole budget instead, 10 Hz commands pushed the link's schedule back after each release, and
    /// hazards planned to leave in time were doomed (a robot at a grant of 31,000 bit/s beside 19,360 of
    /// commands: one A in 40 lost).
    void set_rate(double sensed_rate_bps, double steady_outside_bps = 0.0);
    /// The least part of budget_fraction the samples keep whatever the traffic from outside: the gateway's status
    /// still leaves to ask for more.
    static constexpr double MIN_SCHEDULED_SHARE = 0.1;
    /// The last sensed rate.
    double rate_bps() const { return sensed_rate_bps_; }
    /// What the budget spends: the sensed rate times budget_fraction.
    double budget_rate_bps() const { return budget_.rate_bps(); }

    /// Count traffic the scheduler did not release but that shares the link (the WAN participant's discovery,
    /// heartbeats and repairs). What the reserve (the rate the budget does not spend, saved up over
    /// reserve_window) covers costs nothing more; beyond it the link is busy with it before the next sample
    /// goes, up to link_queue ahead.
    void charge_link(base::SteadyTime now, std::uint64_t bits);

    /// The link's own queue holds `bits` now (a shaper's backlog, read by the rate sensor). Nothing more is
    /// released until it has drained at the sensed rate, so a queue that discovery traffic or a sensor reading
    /// high left behind drains instead of standing.
    void observe_link_backlog(base::SteadyTime now, std::uint64_t bits);

    /// A sample `sink.forward` took turned out not to be written (ForwardingLoop writes after deciding, see
    /// WriteOutbox): it counts as DropReason::write_failed instead of forwarded. The sink kept it as such. Its
    /// link time stays charged: whether any of it left is not known.
    void forward_failed(TopicId topic, std::size_t payload_bytes);
    /// The same for a sample that left in a bundle whose write failed, or in chunks one of which did: its share of
    /// the bundle's bytes (0 for a sample sent in chunks: a chunk's bytes stay counted, as when a chunked sample
    /// is abandoned).
    void forward_failed(TopicId topic, std::size_t payload_bytes, std::uint64_t wire_bytes);
    /// A chunk (Sample::Chunk::id) that the sink took turned out not to be written. If its sample is still leaving
    /// in chunks, it can no longer arrive whole: it goes to `sink.drop` as DropReason::write_failed, and true.
    /// False when the sample has left already (its last chunk was taken too): see forward_failed.
    bool chunk_failed(std::uint32_t chunk_id, SampleSink& sink);
    /// Everything still queued goes to `sink.drop` with `reason` (shutdown).
    void drain(SampleSink& sink, DropReason reason = DropReason::shutdown);

    const TopicCounters& counters(TopicId topic) const { return topics_[topic].counters; }
    /// Every topic's counts, retired ones included.
    TopicCounters total_counters() const;
    /// The counts retired topics took with them, summed.
    const TopicCounters& retired_counters() const { return retired_counters_; }
    std::size_t queued_samples() const { return queue_.size() + (chunked_ ? 1 : 0); }
    std::size_t queued_bytes() const { return queue_.memory_bytes(); }
    const SchedulerConfig& config() const { return config_; }

  private:
    /// The bits a sample of `payload_bytes` puts on the link.
    std::uint64_t wire_bits(std::size_t payload_bytes) const { return config_.wire.wire_bits(payload_bytes); }
    /// The bits the sample puts on the link sent alone: its own DDS sample, or a bundle of its own.
    std::uint64_t alone_wire_bits(const Sample& sample) const;

    struct TopicState {
        TopicConfig config;
        TopicCounters counters;
        base::SteadyTime last_arrival{};
        std::uint64_t last_wire_bits = 0;
        bool seen = false;
        /// protect_epoch_ when this topic's present limit was last offered to protect_.
        std::uint64_t protect_epoch = 0;
        /// Compact mode: the link bits its entries took lately, their share of the bundle headers included.
        DecayingRate link_use;
        bool reachable = true;  ///< see set_reachable
        bool retired = false;   ///< see retire_topic
        /// The last sample's source time and the steady time it was taken to be born at (push).
        base::WallTime last_source_time{};
        base::SteadyTime last_origin{};
        std::optional<RateCap> rate_cap;  ///< config.max_rate_hz's
    };

    static TopicState fresh_topic(const TopicConfig& topic);
    /// A queued sample as a bundle entry, to size it without taking it from the queue.
    static BundleBuilder::Entry peeked_entry(const DeadlineQueue::Peek& peek) {
        return BundleBuilder::Entry::of(peek.topic, peek.route, peek.source_time, *peek.payload, peek.keyed);
    }

    bool active(TopicId topic, base::SteadyTime now) const;
    base::Duration protect_limit(TopicId topic) const;
    const ProtectedTopics& protected_topics(base::SteadyTime now);
    /// How long a sample of `topic` may hold the link (ProtectedTopics::limit_for).
    base::Duration protect_limit_for(TopicId topic) const { return protect_.limit_for(topic, protect_rank_of(topic)); }
    std::int64_t rank_of(TopicId topic) const;
    /// A repair's rank: its sample's topic's, or for an announcement that of a sample of ANNOUNCEMENT_TTL.
    std::int64_t rank_of(const Repair& repair) const;
    /// How long a repair may hold the link: as a sample of its topic, or for an announcement of its rank.
    base::Duration protect_limit_for(const Repair& repair) const;
    /// Its rank as the non-preemptive rule sees it: by its TTL under ttl, `first` or not. A status that goes first
    /// is still held to the room of the topics of its TTL and shorter (it leaves in chunks, or waits): the least
    /// share leaves room for it beside the most urgent topic (core::least_share_bps).
    std::int64_t protect_rank_of(TopicId topic) const;
    Sample take(DeadlineQueue::Slot slot);
    void forward(Sample&& sample, std::uint64_t wire_bits, SampleSink& sink);
    void drop(Sample&& sample, DropReason reason, SampleSink& sink);
    void expire(base::SteadyTime now, SampleSink& sink);
    void evict_over_cap(SampleSink& sink);
    void release_by_deadline(base::SteadyTime now, SampleSink& sink);
    void release_bundles(base::SteadyTime now, SampleSink& sink);
    /// Fills one bundle from the queue, starting on the link at `start`; empty when nothing may go now.
    std::vector<Sample> fill_bundle(base::SteadyTime start, BundleBuilder& bundle, SampleSink& sink);
    /// The sample in `slot` is too large for a bundle, or would hold the link too long: it leaves in chunks
    /// from now on, if all of them can still arrive in time (else it is logged as doomed). False if not started.
    bool start_chunks(DeadlineQueue::Slot slot, base::SteadyTime start, SampleSink& sink);
    /// Adds the next chunk of the chunked sample to `bundle`, as large as the bundle's room, its entries'
    /// deadlines and `limit` (the non-preemptive rule) allow. False when not even a small one fits.
    bool add_chunk(base::SteadyTime start, base::SteadyTime earliest_deadline, base::Duration limit,
                   BundleBuilder& bundle, std::vector<Sample>& samples);
    /// Compact mode: the budget's rate less what the topics more urgent than `rank` spent of the link lately.
    double rate_left_bps(std::int64_t rank, base::SteadyTime at) const;
    /// The chunked sample goes to the log with `reason`; its chunks already sent are wasted.
    void abandon_chunks(DropReason reason, SampleSink& sink);
    /// Whether the sample of a `first` topic at the head of the queue yields the send from `start` to the most
    /// urgent other sample (TopicConfig::yields_within): when it does, by when what goes in its place must have
    /// arrived for it still to arrive in time after.
    std::optional<base::SteadyTime> first_yields(base::SteadyTime start);
    /// The first sample of a bundle (or a sample of its own): drops it when it can no longer arrive in time,
    /// holds it back when its wire time would cost the most urgent topic its deadline. True if it may go.
    bool may_start(DeadlineQueue::Slot slot, base::SteadyTime start, std::uint64_t bits, SampleSink& sink);
    void release_paper_period(base::SteadyTime now, SampleSink& sink);
    /// Asks the idle source for samples while nothing else wants the link, and releases them.
    void fill_idle(base::SteadyTime now, SampleSink& sink);
    /// When the idle source's next sample could go (next_wakeup with nothing queued).
    std::optional<base::SteadyTime> idle_wakeup(base::SteadyTime now) const;
    /// Where a queued sample stands in the order of urgency, for repairs to be compared with.
    struct UrgencyKey {
        std::int64_t rank;
        base::SteadyTime deadline;
    };
    /// Sends the most urgent repair that is more urgent than `bound` (any, for nullopt) and may start at `start`;
    /// discards on the way those that can no longer arrive in time. True when one was sent.
    bool send_repair_before(const std::optional<UrgencyKey>& bound, base::SteadyTime now, base::SteadyTime start,
                            SampleSink& sink);
    void send_repair_now(const Repair& repair, SampleSink& sink);
    /// Compact mode: a bundle carries the most urgent samples with the rest, so a queue that always holds a hazard
    /// would keep an announcement waiting for its whole wait. It steals the slack instead: the first one waiting
    /// goes now, starting on the link at `start`, if every queued sample more urgent than it still arrives in time
    /// behind it.
    bool send_announcement_in_slack(base::SteadyTime now, base::SteadyTime start, SampleSink& sink);
    /// Whether `repair` is a continuation whose sample was cut short already: its other fragments are of no use.
    bool cut_short(const Repair& repair) const;
    void note_cut_short(const Repair& continuation, DropReason reason);
    /// A repair that can no longer arrive in time is discarded; an announcement is sent all the same, charged as
    /// traffic from outside the schedule, or left out when it is skippable and would hold the link too long.
    void give_up_repair(const Repair& repair, base::SteadyTime now, SampleSink& sink);

    SchedulerConfig config_;
    std::vector<TopicState> topics_;
    std::vector<TopicId> free_topics_;  ///< retired slots add_topic() may take
    std::size_t retired_slots_ = 0;
    std::size_t queued_first_ = 0;  ///< samples of `first` topics in queue_
    TopicCounters retired_counters_;
    DeadlineQueue queue_;
    LatestSamples latest_;
    double sensed_rate_bps_;
    LinkBudget budget_;
    LinkReserve reserve_;  ///< for charge_link
    std::uint64_t next_sequence_ = 0;
    PaperFilter paper_;  ///< `paper` only
    ProtectedTopics protect_;
    bool protect_valid_ = false;
    std::uint64_t protect_epoch_ = 0;
    base::SteadyTime protect_built_at_{};
    /// When a sample held back by the non-preemptive rule must be looked at again; set by release().
    std::optional<base::SteadyTime> blocked_wakeup_;
    /// The last samples cut short (Repair::sample; 0 is none).
    std::array<std::uint64_t, 8> cut_short_{};
    std::size_t next_cut_short_ = 0;

    /// Compact WAN mode: the sample leaving in chunks, at most one at a time. Counted as queued until its last
    /// chunk leaves.
    struct ChunkedSample {
        std::uint32_t id = 0;  ///< Sample::Chunk::id of its chunks
        Sample sample;
        std::int64_t rank = 0;
        std::size_t sent_bytes = 0;
    };
    std::optional<ChunkedSample> chunked_;
    std::optional<ChunkPlanning> chunk_planning_;  ///< compact WAN mode's
    IdleSource* idle_ = nullptr;                   ///< see set_idle_source
    TopicId idle_topic_ = 0;
    std::uint32_t next_chunk_id_ = 0;

    RepairQueue repairs_;
    RepairCounters repair_counters_;
};

}  // namespace tgw::core
