#include <gtest/gtest.h>

#include <random>

#include "core/urgency_demand.hpp"
#include "test/unit/core/scheduler_fixture.hpp"

namespace tgw::core {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

class SchedulerTest : public SchedulerFixture {
  protected:
    /// With the link busy, two A samples (TTL 1 s) queue, then one of a `first` topic of the same TTL: which
    /// topic leaves next ("status" or "A").
    std::string second_sent_with_a_first_topic(PolicyKind policy) {
        make_sut(policy, 10'000);
        const TopicId status = sut->add_topic({"status", seconds(1), true});
        push(c);
        release();  // occupies the link
        push(a, 64, milliseconds(300));
        push(a, 64, milliseconds(200));
        push(status);  // its deadline the latest of the three
        run_for(seconds(1));
        const std::vector<TopicId> sent = sink.forwarded_topics();
        return sent.size() < 2 ? "nothing" : sent[1] == status ? "status" : sent[1] == a ? "A" : "other";
    }

    struct StatusRun {
        TopicId status;
        std::vector<TopicId> sent;
    };

    /// At 10,000 bit/s, with C on the link (about 0.19 s), an A sample aged 500 ms (due in 0.5 s: at 0.38 s alone,
    /// at 0.88 s behind the status), then a 450-byte sample of `status_topic` (a `first` topic) aged `status_age`:
    /// what left within a second.
    StatusRun sent_beside_a_450_byte_status(const TopicConfig& status_topic, base::Duration status_age = {}) {
        make_sut(PolicyKind::ttl, 10'000);
        const TopicId status = sut->add_topic(status_topic);
        push(c);
        release();
        push(a, 64, milliseconds(500));
        push(status, 450, status_age);
        run_for(seconds(1));
        return {status, sink.forwarded_topics()};
    }

    /// Wire time of a 64-byte sample at `rate_bps` under the default wire model.
    base::Duration wire_time_64(double rate_bps) const {
        return base::from_seconds(static_cast<double>(config.wire.wire_bits(64)) / rate_bps);
    }
};

TEST_F(SchedulerTest, CountsARefusedWriteAsWriteFailedNotForwarded) {
    make_sut(PolicyKind::ttl, 100'000);
    sink.refuse_writes();
    push(a);
    release();
    const TopicCounters counters = sut->counters(a);
    EXPECT_EQ(counters.forwarded, 0u);
    EXPECT_EQ(counters.forwarded_payload_bytes, 0u);
    EXPECT_EQ(counters.dropped_for(DropReason::write_failed), 1u);
    EXPECT_EQ(sink.dropped_count(DropReason::write_failed), 1u);
    EXPECT_EQ(counters.received, counters.forwarded + counters.queued + counters.dropped_total());
}

// The base camp's grants count a topic that began lately over the time since its first sample (urgency_demand).
TEST_F(SchedulerTest, RemembersWhenATopicsFirstSampleArrived) {
    make_sut(PolicyKind::ttl, 100'000);
    EXPECT_FALSE(sut->counters(a).first_received);
    const base::SteadyTime first = clock.now();
    push(a);
    clock.advance(seconds(1));
    push(a);
    release();
    ASSERT_TRUE(sut->counters(a).first_received);
    EXPECT_EQ(*sut->counters(a).first_received, first);
    EXPECT_FALSE(sut->counters(b).first_received);
}

TEST_F(SchedulerTest, KeepsABurstInItsSourceOrderWhenTheWallClockIsReadLate) {
    make_sut(PolicyKind::ttl, 1'000);  // slow: the burst queues, about 2 s a sample
    for (std::uint8_t i = 0; i < 3; ++i) {
        Sample s;
        s.topic = d;
        s.payload.assign(64, i);
        s.source_time = clock.wall_now() + std::chrono::microseconds(i);  // a burst, a microsecond apart
        // The wall clock read 2 ms after the steady one for the second sample (a preemption between the reads).
        const base::WallTime wall =
            clock.wall_now() + (i == 1 ? std::chrono::milliseconds(2) : base::WallClock::duration{});
        sut->push(std::move(s), clock.now(), wall, sink);
    }
    run_for(seconds(8));
    std::vector<std::uint8_t> order;
    for (const Sample& s : sink.forwarded()) {
        order.push_back(s.payload.front());
    }
    EXPECT_EQ(order, (std::vector<std::uint8_t>{0, 1, 2}));
}

TEST_F(SchedulerTest, SendsAtOnceWhenTheLinkIsFree) {
    make_sut(PolicyKind::ttl, 100'000);
    push(d);
    release();
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{d}));
}

TEST_F(SchedulerTest, TtlPolicySendsShortestTtlFirstWhileTheLinkIsBusy) {
    make_sut(PolicyKind::ttl, 10'000);
    push(d);
    release();  // D occupies the link
    push(d);
    push(c);
    push(b);
    push(a);
    run_for(seconds(2));
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{d, a, b, c, d}));
}

TEST_F(SchedulerTest, TtlPolicyPrefersShortTtlEvenOverAnOlderLongTtlSampleDueSooner) {
    make_sut(PolicyKind::ttl, 10'000);
    push(c);
    release();                          // occupies the link
    push(d, 64, milliseconds(19'500));  // due in 0.5 s
    push(a);                            // due in 1 s
    run_for(milliseconds(200));
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{c, a}));
}

TEST_F(SchedulerTest, EdfPolicySendsNearestDeadlineFirstAcrossTopics) {
    make_sut(PolicyKind::edf, 10'000);
    push(c);
    release();
    push(d, 64, milliseconds(19'500));  // due in 0.5 s
    push(a);                            // due in 1 s
    run_for(milliseconds(200));
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{c, d}));
}

TEST_F(SchedulerTest, AFirstTopicLeavesBeforeABacklogOfItsTtlUnderTtl) {
    EXPECT_EQ(second_sent_with_a_first_topic(PolicyKind::ttl), "status");
}

TEST_F(SchedulerTest, AFirstTopicLeavesBeforeNearerDeadlinesUnderEdf) {
    EXPECT_EQ(second_sent_with_a_first_topic(PolicyKind::edf), "status");
}

TEST_F(SchedulerTest, EqualTtlSamplesGoNearestDeadlineFirst) {
    make_sut(PolicyKind::ttl, 10'000);
    push(c);
    release();
    push(b, 64, milliseconds(100));
    push(b, 65, milliseconds(900));
    run_for(seconds(1));
    const auto sent = sink.forwarded();
    ASSERT_EQ(sent.size(), 3u);
    EXPECT_EQ(sent[1].payload.size(), 65u);
}

TEST_F(SchedulerTest, LogsSamplesThatExpireWhileQueued) {
    make_sut(PolicyKind::ttl, 0.0);
    push(a);
    push(b);
    run_for(milliseconds(1'500));
    EXPECT_EQ(sink.dropped_count(DropReason::expired), 1u);
    EXPECT_EQ(sut->queued_samples(), 1u);
}

TEST_F(SchedulerTest, LogsSampleAlreadyExpiredOnArrival) {
    make_sut(PolicyKind::ttl, 100'000);
    push(a, 64, milliseconds(1'200));
    EXPECT_EQ(sink.dropped_count(DropReason::expired), 1u);
    EXPECT_EQ(sut->queued_samples(), 0u);
}

TEST_F(SchedulerTest, DropsEarlyASampleThatCanNoLongerArriveInTime) {
    make_sut(PolicyKind::ttl, 10'000);
    const base::Duration tx = wire_time_64(10'000);
    push(a, 64, seconds(1) - tx / 2);  // half its wire time left
    release();
    EXPECT_EQ(sink.dropped_count(DropReason::doomed), 1u);
    EXPECT_TRUE(sink.forwarded().empty());
}

TEST_F(SchedulerTest, CountsLinkLatencyWhenJudgingWhetherASampleCanArrive) {
    config.link_latency = milliseconds(300);
    make_sut(PolicyKind::ttl, 100'000);
    push(a, 64, milliseconds(800));
    release();
    EXPECT_EQ(sink.dropped_count(DropReason::doomed), 1u);
}

TEST_F(SchedulerTest, ZeroRateKeepsSamplesUntilTheirDeadlineInsteadOfDroppingThemEarly) {
    make_sut(PolicyKind::ttl, 0.0);
    push(d);
    run_for(seconds(10));
    EXPECT_EQ(sut->queued_samples(), 1u);
    sut->set_rate(100'000);
    release();
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{d}));
}

TEST_F(SchedulerTest, EvictsLeastUrgentSampleWhenOverMemoryCap) {
    config.memory_cap_bytes = 3 * (1'000 + DeadlineQueue::BOOKKEEPING_BYTES);
    make_sut(PolicyKind::ttl, 0.0);
    push(a, 1'000);
    push(d, 1'000);
    push(b, 1'000);
    push(c, 1'000);
    const auto dropped = sink.dropped();
    ASSERT_EQ(dropped.size(), 1u);
    EXPECT_EQ(dropped[0].reason, DropReason::evicted);
    EXPECT_EQ(dropped[0].sample.topic, d);
    EXPECT_LE(sut->queued_bytes(), config.memory_cap_bytes);
}

TEST_F(SchedulerTest, HoldsBackALargeSampleThatWouldMakeTheMostUrgentTopicMissItsDeadline) {
    make_sut(PolicyKind::ttl, 10'000);
    push(a);
    release();
    push(d, 6'000);  // about 5 s on the wire at 10 kbit/s: A could not get through for 5 s
    run_for(seconds(1));
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{a}));
    EXPECT_EQ(sut->queued_samples(), 1u);
}

TEST_F(SchedulerTest, SendsAHeldBackLargeSampleOnceTheLinkIsFastEnough) {
    make_sut(PolicyKind::ttl, 10'000);
    push(a);
    release();
    push(d, 6'000);
    run_for(seconds(1));
    sut->set_rate(200'000);
    run_for(milliseconds(10));
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{a, d}));
}

TEST_F(SchedulerTest, LogsAHeldBackSampleAsOversizeWhenItCanNoLongerMakeItsDeadline) {
    make_sut(PolicyKind::ttl, 10'000);
    push(d, 6'000);
    for (int i = 0; i < 100; ++i) {  // A stays active at 5 Hz for 20 s
        push(a);
        run_for(milliseconds(200));
    }
    EXPECT_EQ(sink.dropped_count(DropReason::oversize), 1u);
    EXPECT_EQ(sut->counters(a).forwarded, 100u);
    EXPECT_EQ(sut->queued_samples(), 0u);
}

// The status under --channel-grants (a first topic) at a robot's least share, as the base camp grants it: it must
// not be held back for the most urgent topic's sake, or the base camp never hears of the demand that would raise
// the share (ChannelGrantTest: a robot kept 2,375 bit/s for good while its hazards waited).
TEST_F(SchedulerTest, AtTheLeastShareTheStatusLeavesBesideTheMostUrgentTopic) {
    const std::size_t status_bytes = 450;
    const std::vector<TopicLoad> loads = {
        TopicLoad{"A", seconds(1), 10, 10, 10 * config.wire.wire_bytes(64), 0, 0, 10 * 64}};
    make_sut(PolicyKind::ttl, least_share_bps(loads, status_bytes, seconds(1), {config.wire}));
    const TopicId status = sut->add_topic({"status", seconds(5), true});
    push(a);
    run_for(milliseconds(500));  // A has left and is still active: the topic the non-preemptive rule protects
    push(status, status_bytes);
    run_for(seconds(1));
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{a, status}));
}

// The status first, at a small share: a 450-byte status is half a second of wire at 10,000 bit/s, and an A sample
// due sooner would expire behind it (three robots on grants lost A three at a time, once per status). It yields
// where the A makes its deadline going before and the status still makes its own after.
TEST_F(SchedulerTest, TheStatusYieldsToTheSampleItWouldCostItsDeadline) {
    const StatusRun run = sent_beside_a_450_byte_status({"status", seconds(5), true, seconds(1)});  // the gateway's
    EXPECT_EQ(run.sent, (std::vector<TopicId>{c, a, run.status}));
    EXPECT_EQ(sut->counters(a).dropped_total(), 0u);
}

TEST_F(SchedulerTest, TheStatusDoesNotYieldWhereWaitingWouldCostItsOwnDeadline) {
    // Due in 0.8 s: at 0.69 s first, at 0.88 s after A.
    const StatusRun run = sent_beside_a_450_byte_status({"status", seconds(1), true, seconds(1)}, milliseconds(200));
    EXPECT_EQ(run.sent, (std::vector<TopicId>{c, run.status}));
}

// Its deadline 5 s away, it still yields only while it arrives within a second of its birth: a starved robot's
// status yielding for seconds kept the base camp from hearing the demand that would raise its grant.
TEST_F(SchedulerTest, TheStatusYieldsOnlyWhileItStillArrivesWithinItsYieldWindow) {
    // Born 0.5 s ago: after A it would arrive 1.38 s after its birth.
    const StatusRun run = sent_beside_a_450_byte_status({"status", seconds(5), true, seconds(1)}, milliseconds(500));
    EXPECT_EQ(run.sent, (std::vector<TopicId>{c, run.status}));
}

TEST_F(SchedulerTest, AFirstTopicWithoutAYieldWindowNeverYields) {
    const StatusRun run = sent_beside_a_450_byte_status({"status", seconds(5), true});
    EXPECT_EQ(run.sent, (std::vector<TopicId>{c, run.status}));
}

// The non-preemptive rule protects a topic from what is less urgent than it, not from what is more urgent: a
// 6 kB picture (TTL 5 s) at 12,000 bit/s leaves itself 0.38 s, and a 1 kB sample of TTL 2 s takes 0.78 s. Under
// ttl it would go before the picture anyway; held back for it, it waited until the picture's topic went quiet.
TEST_F(SchedulerTest, ALessUrgentTopicsProtectionDoesNotHoldBackAMoreUrgentSample) {
    make_sut(PolicyKind::ttl, 12'000);
    push(c, 6'000);
    run_for(milliseconds(4'700));  // the picture has left (4.62 s); its topic is still active
    ASSERT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{c}));
    push(b, 1'000);
    release();
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{c, b}));
}

// A topic whose own sample takes longer than its TTL at the rate cannot be protected: its limit is negative, and
// held to it every other topic stopped (a robot at its least share with a camera: nothing left for 30 s).
TEST_F(SchedulerTest, ATopicThatCannotMakeItsTtlAtTheRateProtectsNoOne) {
    make_sut(PolicyKind::edf, 7'600);
    const TopicId camera = sut->add_topic({"camera", seconds(5)});
    push(camera, 6'000);  // 7.3 s on the wire
    release();
    run_for(milliseconds(100));
    for (int i = 0; i < 10; ++i) {
        push(a);  // 0.25 s on the wire, every 0.4 s
        run_for(milliseconds(400));
    }
    EXPECT_EQ(sut->counters(a).forwarded, 10u);
}

TEST_F(SchedulerTest, LargeSamplesAreNotHeldBackOnceNoShortTtlTopicIsActive) {
    make_sut(PolicyKind::ttl, 10'000);
    push(a);
    release();
    clock.advance(seconds(2));  // A has gone quiet for longer than its TTL
    push(d, 6'000);
    release();
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{a, d}));
}

TEST_F(SchedulerTest, HoldsBackALargeSampleForATopicThatArrivedAfterTheLastRelease) {
    make_sut(PolicyKind::ttl, 10'000);
    push(d);
    release();  // only D is active here
    push(d, 6'000);
    push(a);  // A becomes the topic to protect between two releases
    run_for(seconds(1));
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{d, a}));
    EXPECT_EQ(sut->queued_samples(), 1u);
}

TEST_F(SchedulerTest, ProtectsByTheTtlATopicHasNow) {
    make_sut(PolicyKind::ttl, 10'000);
    push(c);
    release();
    clock.advance(seconds(1));
    push(d, 8'000);  // about 6.5 s on the wire: longer than C's 5 s TTL
    release();
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{c}));

    sut->set_ttl(c, seconds(30));
    release();
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{c, d}));
}

TEST_F(SchedulerTest, TrafficChargedFromOutsideDelaysTheNextSample) {
    make_sut(PolicyKind::ttl, 10'000);
    sut->charge_link(clock.now(), 5'000);  // half a second of discovery traffic
    push(a);
    release();
    EXPECT_TRUE(sink.forwarded().empty());
    run_for(milliseconds(500));
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{a}));
}

TEST_F(SchedulerTest, OutsideTrafficHoldsTheLinkNoLongerThanItsQueue) {
    make_sut(PolicyKind::ttl, 10'000);      // link_queue: 1 s by default
    sut->charge_link(clock.now(), 50'000);  // 5 s of a discovery burst: a 1 s queue drops the rest
    push(d);
    run_for(milliseconds(999));
    EXPECT_TRUE(sink.forwarded().empty());
    run_for(milliseconds(1));
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{d}));
}

TEST_F(SchedulerTest, TheUnspentRestOfTheRateCoversOutsideTrafficThatFitsInIt) {
    config.policy = PolicyKind::ttl;
    config.initial_rate_bps = 10'000;
    config.lead = base::Duration::zero();
    config.budget_fraction = 0.9;  // 1,000 bit/s saved for outside traffic, over 20 s at most
    Scheduler scheduler(config);
    const TopicId t = scheduler.add_topic({"A", seconds(1)});
    auto send_one = [&] {
        Sample s;
        s.topic = t;
        s.payload.assign(64, 1);
        s.source_time = clock.wall_now();
        scheduler.push(std::move(s), clock.now(), clock.wall_now(), sink);
        scheduler.release(clock.now(), sink);
    };
    scheduler.charge_link(clock.now(), 0);  // the reserve starts filling now
    clock.advance(seconds(30));
    scheduler.charge_link(clock.now(), 20'000);  // an announcement burst the saved 20,000 bits cover
    send_one();
    EXPECT_EQ(sink.forwarded().size(), 1u) << "traffic the reserve covered held the link";
    clock.advance(seconds(1));
    scheduler.charge_link(clock.now(), 5'000);  // 1,000 bits saved since: 4,000 at 9,000 bit/s hold it 0.44 s
    send_one();
    EXPECT_EQ(sink.forwarded().size(), 1u);
    clock.advance(milliseconds(440));
    scheduler.release(clock.now(), sink);
    EXPECT_EQ(sink.forwarded().size(), 1u);
    clock.advance(milliseconds(5));
    scheduler.release(clock.now(), sink);
    EXPECT_EQ(sink.forwarded().size(), 2u);
}

// The base camp's commands at 10 Hz (1,936 bits on the wire each) on a half-duplex 30,000 bit/s link, told as
// 20,000 bit/s of steady traffic from outside: the budget spends the rest, and the commands, charged as they come,
// fall to what it leaves them. A hazard every 200 ms leaves the moment it comes, every time.
TEST_F(SchedulerTest, SteadyTrafficFromOutsideIsLeftItsRateAndHoldsNoSample) {
    make_sut(PolicyKind::ttl, 30'000);
    sut->set_rate(30'000, 20'000);
    EXPECT_DOUBLE_EQ(sut->budget_rate_bps(), 10'000);
    sut->charge_link(clock.now(), 0);  // the reserve starts filling now
    for (int i = 1; i <= 50; ++i) {
        clock.advance(milliseconds(100));
        sut->charge_link(clock.now(), 1'936);
        if (i % 2 == 0) {
            push(a, 41);
            release();
            EXPECT_EQ(sink.forwarded().size(), static_cast<std::size_t>(i / 2)) << "held at " << i * 100 << " ms";
        }
    }
    // The same commands charged against the whole budget hold the hazards back.
    make_sut(PolicyKind::ttl, 10'000);
    const std::size_t before = sink.forwarded().size();
    sut->charge_link(clock.now(), 1'936);
    push(a, 41);
    release();
    EXPECT_EQ(sink.forwarded().size(), before);
    // Whatever comes from outside, the samples keep a part of the budget.
    sut->set_rate(30'000, 50'000);
    EXPECT_DOUBLE_EQ(sut->budget_rate_bps(), 30'000 * Scheduler::MIN_SCHEDULED_SHARE);
}

TEST_F(SchedulerTest, WaitsForABacklogSeenInTheLinkToDrain) {
    make_sut(PolicyKind::ttl, 10'000);
    sut->observe_link_backlog(clock.now(), 3'000);  // 300 ms of someone else's traffic in the shaper
    push(a);
    run_for(milliseconds(299));
    EXPECT_TRUE(sink.forwarded().empty());
    run_for(milliseconds(1));
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{a}));
}

TEST_F(SchedulerTest, ABacklogOfItsOwnSamplesDoesNotDelayTheNextOneTwice) {
    make_sut(PolicyKind::ttl, 10'000);
    push(a);
    release();                                                          // the link is busy with it for its wire time
    sut->observe_link_backlog(clock.now(), config.wire.wire_bits(64));  // the shaper holds that same sample
    push(a);
    run_for(wire_time_64(10'000));
    EXPECT_EQ(sink.forwarded().size(), 2u);
}

TEST_F(SchedulerTest, PacesReleasesAtTheLinkRate) {
    make_sut(PolicyKind::ttl, 20'000);
    for (int i = 0; i < 100; ++i)
        push(d, 500);
    run_for(seconds(10));
    const auto& counters = sut->counters(d);
    const double sent_bits = 8.0 * static_cast<double>(counters.forwarded_wire_bytes);
    EXPECT_LE(sent_bits, 20'000.0 * 10 + 8.0 * static_cast<double>(config.wire.wire_bytes(500)));
    EXPECT_GE(sent_bits, 20'000.0 * 9);
}

TEST_F(SchedulerTest, BudgetSpendsOnlyItsFractionOfTheSensedRate) {
    make_sut(PolicyKind::ttl, 20'000);
    sut->set_rate(40'000);
    EXPECT_EQ(sut->rate_bps(), 40'000);
    EXPECT_EQ(sut->budget_rate_bps(), 40'000);
    SchedulerConfig c;
    c.initial_rate_bps = 40'000;
    c.budget_fraction = 0.9;
    Scheduler with_margin(c);
    EXPECT_EQ(with_margin.rate_bps(), 40'000);
    EXPECT_DOUBLE_EQ(with_margin.budget_rate_bps(), 36'000);
    with_margin.set_rate(10'000);
    EXPECT_DOUBLE_EQ(with_margin.budget_rate_bps(), 9'000);
}

TEST_F(SchedulerTest, PaperPolicySendsWhatFitsInRateTimesPeriodShortestTtlFirst) {
    config.paper_period = seconds(1);
    make_sut(PolicyKind::paper, 8 * 200);  // 200 payload bytes per period
    push(d, 150);
    push(c, 100);
    push(a, 60);
    push(b, 60);
    release();
    // A (60) and B (60) fit, C (100) would not, D (150) would not; the paper walks on past a misfit.
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{a, b}));
    clock.advance(milliseconds(500));
    release();
    EXPECT_EQ(sink.forwarded().size(), 2u);  // waits for the next period
    clock.advance(milliseconds(500));
    release();
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{a, b, c}));
}

TEST_F(SchedulerTest, PaperPolicyAssumedOverheadShrinksWhatFits) {
    config.paper_overhead = 0.5;
    make_sut(PolicyKind::paper, 8 * 200);
    push(a, 100);
    push(b, 100);
    release();
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{a}));
}

TEST_F(SchedulerTest, FifoForwardsAtOnceWithoutBudget) {
    make_sut(PolicyKind::fifo, 0.0);
    push(d, 5'000);
    push(a);
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{d, a}));
    EXPECT_FALSE(sut->next_wakeup(clock.now()));
}

TEST_F(SchedulerTest, DrainLogsEverythingQueuedAsShutdown) {
    make_sut(PolicyKind::ttl, 0.0);
    push(a);
    push(d);
    sut->drain(sink);
    EXPECT_EQ(sink.dropped_count(DropReason::shutdown), 2u);
    EXPECT_EQ(sut->queued_samples(), 0u);
}

TEST_F(SchedulerTest, NextWakeupIsWhenTheLinkFreesOrTheEarliestDeadline) {
    make_sut(PolicyKind::ttl, 10'000);
    push(a);
    push(b);
    release();
    EXPECT_EQ(*sut->next_wakeup(clock.now()), clock.now() + wire_time_64(10'000));
    sut->set_rate(0.0);
    EXPECT_EQ(*sut->next_wakeup(clock.now()), clock.now() + seconds(2));
}

TEST_F(SchedulerTest, SourceClockAheadOfTheGatewayDoesNotLengthenTheDeadline) {
    make_sut(PolicyKind::ttl, 0.0);
    push(a, 64, -seconds(30));  // stamped 30 s in the future
    run_for(milliseconds(1'001));
    EXPECT_EQ(sink.dropped_count(DropReason::expired), 1u);
}

TEST_F(SchedulerTest, ArrivalClockIgnoresTheSourceTimestamp) {
    config.trust_source_clock = false;
    make_sut(PolicyKind::ttl, 0.0);
    push(a, 64, seconds(30));  // stamped long ago by a skewed clock
    EXPECT_EQ(sut->queued_samples(), 1u);
}

TEST_F(SchedulerTest, EverySampleIsForwardedQueuedOrLogged) {
    config.memory_cap_bytes = 40'000;
    make_sut(PolicyKind::ttl, 15'000);
    run_random_load(7, 5'000);
    for (TopicId t : {a, b, c, d}) {
        const TopicCounters& n = sut->counters(t);
        EXPECT_TRUE(n.balanced()) << "topic " << t;
    }
    const TopicCounters total = sut->total_counters();
    EXPECT_EQ(total.received, 5'000u);
    EXPECT_EQ(total.forwarded, sink.forwarded().size());
    EXPECT_EQ(total.dropped_total(), sink.dropped().size());
    EXPECT_EQ(total.queued, sut->queued_samples());
    EXPECT_GT(total.forwarded, 0u);
    EXPECT_GT(total.dropped_total(), 0u);
}

}  // namespace
}  // namespace tgw::core
