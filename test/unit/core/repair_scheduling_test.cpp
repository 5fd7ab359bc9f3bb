// Repairs for reliable readers in the schedule: in the urgency of the sample they repair, charged when they leave,
// never sent once they cannot arrive in time.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test/unit/core/scheduler_fixture.hpp"

namespace tgw::core {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
using Departures = std::vector<std::string>;

class RepairSchedulingTest : public SchedulerFixture {
  protected:
    /// A repair of a sample of `topic` due `due_in` from now, of `wire_bytes` on the link.
    void push_repair(std::uint64_t id, TopicId topic, base::Duration due_in, std::uint64_t wire_bytes = 200) {
        sut->push_repair(Repair{id, topic, clock.now() + due_in, 8 * wire_bytes}, clock.now(), sink);
    }
    static std::string sample_of(TopicId topic) { return "sample " + std::to_string(topic); }
    static std::string repair(std::uint64_t id) { return "repair " + std::to_string(id); }
};

TEST_F(RepairSchedulingTest, ARepairOfALessUrgentTopicWaitsBehindAMoreUrgentSample) {
    make_sut(PolicyKind::ttl, 10'000);
    push(c);
    release();  // on the link
    push_repair(1, d, seconds(10));
    push(a);
    run_for(seconds(2));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(c), sample_of(a), repair(1)}));
}

TEST_F(RepairSchedulingTest, ARepairOfAMoreUrgentTopicGoesBeforeALessUrgentSample) {
    make_sut(PolicyKind::ttl, 10'000);
    push(c);
    release();
    push(d);
    push_repair(1, a, milliseconds(900));
    run_for(seconds(2));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(c), repair(1), sample_of(d)}));
}

TEST_F(RepairSchedulingTest, ARepairOfAnOlderSampleGoesBeforeANewerSampleOfItsTopic) {
    make_sut(PolicyKind::ttl, 10'000);
    push(c);
    release();
    push(a);  // due in 1 s
    push_repair(1, a, milliseconds(600));
    run_for(seconds(2));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(c), repair(1), sample_of(a)}));
}

TEST_F(RepairSchedulingTest, ARepairThatCannotArriveInTimeIsDiscardedNotSent) {
    make_sut(PolicyKind::ttl, 10'000);
    push_repair(1, b, milliseconds(500), 1'000);  // 0.8 s of wire
    run_for(seconds(2));
    EXPECT_TRUE(sink.departures().empty());
    EXPECT_EQ(sink.discarded_repairs(), (std::vector<std::uint64_t>{1}));
    EXPECT_EQ(sut->repair_counters().late, 1u);
    EXPECT_EQ(sut->repair_counters().sent, 0u);
    EXPECT_EQ(sut->repair_counters().queued, 0u);
}

TEST_F(RepairSchedulingTest, ARepairWhoseSampleIsPastItsDeadlineBehindTheLinkIsDiscarded) {
    make_sut(PolicyKind::ttl, 10'000);
    push(d, 1'000);  // about 0.9 s on the link
    release();
    push_repair(1, a, milliseconds(500));
    run_for(seconds(2));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(d)}));
    EXPECT_EQ(sink.discarded_repairs(), (std::vector<std::uint64_t>{1}));
    EXPECT_EQ(sut->repair_counters().late, 1u);
}

TEST_F(RepairSchedulingTest, ARepairIsChargedToTheBudgetWhenItLeaves) {
    make_sut(PolicyKind::ttl, 10'000);
    push_repair(1, d, seconds(10), 1'000);  // 0.8 s of wire
    release();
    ASSERT_EQ(sink.departures(), (Departures{repair(1)}));
    push(a);
    release();
    EXPECT_EQ(sink.departures().size(), 1u) << "the repair holds the link";
    run_for(milliseconds(790));
    EXPECT_EQ(sink.departures().size(), 1u);
    run_for(milliseconds(20));
    EXPECT_EQ(sink.departures(), (Departures{repair(1), sample_of(a)}));
    EXPECT_EQ(sut->repair_counters().sent_wire_bytes, 1'000u);
}

TEST_F(RepairSchedulingTest, RepairsNeverCountAsSamples) {
    make_sut(PolicyKind::ttl, 10'000);
    push_repair(1, a, milliseconds(900));
    push_repair(2, a, milliseconds(10));
    run_for(seconds(2));
    const TopicCounters& counters = sut->counters(a);
    EXPECT_EQ(counters.received, 0u);
    EXPECT_EQ(counters.forwarded, 0u);
    EXPECT_EQ(counters.queued, 0u);
    EXPECT_EQ(sut->queued_samples(), 0u);
    EXPECT_TRUE(sink.dropped().empty()) << "a repair never goes to the on-robot log";
    EXPECT_EQ(sut->repair_counters().received, 2u);
    EXPECT_EQ(sut->repair_counters().sent, 1u);
    EXPECT_EQ(sut->repair_counters().late, 1u);
}

TEST_F(RepairSchedulingTest, ARepairLongerThanTheUrgentTopicsRoomWaitsForAFasterLink) {
    make_sut(PolicyKind::ttl, 10'000);
    push(a);
    release();                              // A is active: nothing may hold the link longer than its room (about 0.8 s)
    push_repair(1, d, seconds(15), 1'500);  // 1.2 s of wire
    run_for(milliseconds(500));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(a)}));
    sut->set_rate(100'000);
    run_for(milliseconds(100));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(a), repair(1)}));
}

TEST_F(RepairSchedulingTest, FifoSendsARepairAtOnce) {
    make_sut(PolicyKind::fifo, 10'000);
    push(d, 1'000);
    push_repair(1, a, milliseconds(10), 1'000);
    EXPECT_EQ(sink.departures(), (Departures{sample_of(d), repair(1)}));
}

TEST_F(RepairSchedulingTest, DrainDiscardsTheQueuedRepairs) {
    make_sut(PolicyKind::ttl, 10'000);
    push(d, 1'000);
    release();
    push_repair(1, c, seconds(4));
    push_repair(2, d, seconds(10));
    sut->drain(sink);
    EXPECT_EQ(sink.discarded_repairs(), (std::vector<std::uint64_t>{1, 2}));
    EXPECT_EQ(sut->repair_counters().discarded, 2u);
    EXPECT_EQ(sut->repair_counters().queued, 0u);
}

TEST_F(RepairSchedulingTest, InCompactModeAMoreUrgentRepairGoesBeforeTheNextBundle) {
    config.bundles = BundleLimits{};
    make_sut(PolicyKind::ttl, 10'000);
    push(c);
    release();  // the first bundle, on the link
    push(d);
    push_repair(1, a, milliseconds(900));
    run_for(seconds(2));
    EXPECT_EQ(sink.departures(), (Departures{"bundle", repair(1), "bundle"}));
    ASSERT_EQ(sink.bundles().size(), 2u);
    EXPECT_EQ(sink.bundles()[1].topics, (std::vector<TopicId>{d}));
}

/// The WAN participant's own announcements (Repair::announcement): every 20 s, to each base-camp port it knows,
/// Fast DDS sent them at once; three robots' at the same instant held the channel long enough for A to expire.
class AnnouncementSchedulingTest : public RepairSchedulingTest {
  protected:
    void push_announcement(std::uint64_t id, std::uint64_t wire_bytes = 446, bool skippable = false) {
        Repair announcement{id, 0, clock.now() + ANNOUNCEMENT_WAIT, 8 * wire_bytes};
        announcement.kind = Repair::Kind::announcement;
        announcement.skippable = skippable;
        sut->push_repair(announcement, clock.now(), sink);
    }
};

TEST_F(AnnouncementSchedulingTest, GoesAtOnceOnAnIdleLink) {
    make_sut(PolicyKind::ttl, 10'000);
    push_announcement(1);
    release();
    EXPECT_EQ(sink.departures(), (Departures{repair(1)}));
    EXPECT_EQ(sut->repair_counters().announcements_sent, 1u);
    EXPECT_EQ(sut->repair_counters().sent, 0u) << "not a repair for a reader";
}

TEST_F(AnnouncementSchedulingTest, WaitsBehindUrgentSamplesAndGoesBeforeLessUrgentOnes) {
    make_sut(PolicyKind::ttl, 10'000);
    push(c);
    release();  // on the link
    push(d);
    push_announcement(1);
    push_announcement(2);
    push(a);
    push(b);
    run_for(seconds(2));
    EXPECT_EQ(sink.departures(),
              (Departures{sample_of(c), sample_of(a), sample_of(b), repair(1), repair(2), sample_of(d)}));
}

TEST_F(AnnouncementSchedulingTest, CopiesGoOneAtATimeSoAHazardWaitsForOneAtMost) {
    make_sut(PolicyKind::ttl, 10'000);
    for (std::uint64_t id = 1; id <= 5; ++id)
        push_announcement(id);  // 0.36 s of wire each
    release();
    ASSERT_EQ(sink.departures(), (Departures{repair(1)}));
    push(a);
    run_for(milliseconds(700));  // the second copy leaves behind the hazard, the third not yet
    EXPECT_EQ(sink.departures(), (Departures{repair(1), sample_of(a), repair(2)}))
        << "the hazard goes as soon as the copy on the link has left";
}

TEST_F(AnnouncementSchedulingTest, OneThatWaitedItsWholeWaitIsSentAllTheSameNeverDiscarded) {
    make_sut(PolicyKind::ttl, 1'000);  // a link too slow for anything but the hazards
    for (int i = 0; i < 10; ++i) {
        push(a, 16);
        if (i == 0)
            push_announcement(1);
        run_for(milliseconds(250));
    }
    EXPECT_TRUE(sink.discarded_repairs().empty()) << "the participant's lease depends on it";
    EXPECT_EQ(sut->repair_counters().announcements_sent, 1u);
    EXPECT_EQ(sut->repair_counters().announcements_late, 1u);
}

TEST_F(AnnouncementSchedulingTest, ASkippableOneTooLongForTheLinkAtTheEndOfItsWaitIsLeftOut) {
    make_sut(PolicyKind::ttl, 4'000);  // a dip: a copy is 0.9 s of the link, a hazard may wait 0.5 s at most
    for (int i = 0; i < 10; ++i) {
        push(a, 16);
        if (i == 0)
            push_announcement(1, 446, true);
        run_for(milliseconds(1'000));
    }
    EXPECT_EQ(sink.discarded_repairs(), (std::vector<std::uint64_t>{1}));
    EXPECT_EQ(sut->repair_counters().announcements_skipped, 1u);
    EXPECT_EQ(sut->repair_counters().announcements_sent, 0u);
    EXPECT_EQ(sut->counters(a).forwarded, 10u) << "every hazard on time";
}

TEST_F(AnnouncementSchedulingTest, ASkippableOneIsNotLeftOutWhileTheLinkIsDown) {
    make_sut(PolicyKind::ttl, 25'000);
    sut->set_rate(0);
    push_announcement(1, 446, true);
    run_for(seconds(3));
    EXPECT_EQ(sut->repair_counters().announcements_skipped, 0u);
    EXPECT_EQ(sut->repair_counters().announcements_late, 1u) << "sent at the end of its wait, as before";
}

TEST_F(AnnouncementSchedulingTest, ASkippableOneThatFitsGoesAsAnyOther) {
    make_sut(PolicyKind::ttl, 25'000);
    push(a, 16);
    push_announcement(1, 446, true);
    run_for(seconds(1));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(a), repair(1)}));
    EXPECT_EQ(sut->repair_counters().announcements_skipped, 0u);
}

TEST_F(AnnouncementSchedulingTest, InCompactModeItGoesInTheSlackTheHazardsLeaveNotAtTheEndOfItsWait) {
    // Hazards every 200 ms keep the queue's most urgent sample a hazard: by rank alone the announcement would wait
    // its whole ANNOUNCEMENT_WAIT, then leave with its copies in a burst. It goes before a bundle whose most urgent
    // sample still arrives in time behind it.
    config.bundles = BundleLimits{};
    make_sut(PolicyKind::ttl, 16'000);
    for (std::uint64_t id = 1; id <= 4; ++id)
        push_announcement(id);
    for (int i = 0; i < 15; ++i) {
        push(a);
        push(d, 900);
        run_for(milliseconds(200));
    }
    EXPECT_EQ(sut->repair_counters().announcements_sent, 4u);
    EXPECT_EQ(sut->repair_counters().announcements_late, 0u) << "none waited for its deadline";
    EXPECT_EQ(sut->counters(a).forwarded, 15u);
    EXPECT_EQ(sut->counters(a).dropped_for(DropReason::expired) + sut->counters(a).dropped_for(DropReason::doomed), 0u);
}

TEST_F(AnnouncementSchedulingTest, InCompactModeALessUrgentSampleNearItsDeadlineDoesNotHoldItBack) {
    config.bundles = BundleLimits{};
    make_sut(PolicyKind::ttl, 16'000);
    push(c);
    release();                           // a bundle on the link
    push(d, 900, milliseconds(19'500));  // due in 0.5 s: with the announcement first it would not make it
    push(a);
    push_announcement(1);
    run_for(seconds(1));
    ASSERT_GE(sink.departures().size(), 2u);
    EXPECT_EQ(sink.departures()[1], repair(1)) << "a picture that may miss anyway is not the announcement's concern";
}

/// A WAN writer's announcement (Repair::Kind::writer_announcement): in its topic's urgency, never discarded.
class WriterAnnouncementSchedulingTest : public RepairSchedulingTest {
  protected:
    void push_writer_announcement(std::uint64_t id, TopicId topic, base::Duration wait = ANNOUNCEMENT_WAIT) {
        Repair announcement{id, topic, clock.now() + wait, 8 * 526};  // a DATA(w) as Fast DDS sends it
        announcement.kind = Repair::Kind::writer_announcement;
        sut->push_repair(announcement, clock.now(), sink);
    }
};

TEST_F(WriterAnnouncementSchedulingTest, AHazardsSampleGoesBeforeALogsWriterIsAnnounced) {
    make_sut(PolicyKind::ttl, 20'000);
    push(c);
    release();  // on the link
    push(b);
    push_writer_announcement(1, d);
    push_writer_announcement(2, a, milliseconds(900));
    push(a);
    run_for(seconds(3));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(c), repair(2), sample_of(a), sample_of(b), repair(1)}))
        << "each in its topic's urgency: A's writer before B's sample, D's after it";
    EXPECT_EQ(sut->repair_counters().writer_announcements_sent, 2u);
    EXPECT_EQ(sut->repair_counters().writer_announcements_late, 0u);
    EXPECT_EQ(sut->repair_counters().sent, 0u) << "not a repair for a reader";
}

TEST_F(WriterAnnouncementSchedulingTest, GoesBeforeTheSamplesOfItsTopicQueuedBeforeIt) {
    make_sut(PolicyKind::ttl, 20'000);
    push(d, 600);  // about 0.25 s on the link
    release();
    push(a);
    push(a);
    clock.advance(milliseconds(100));
    push_writer_announcement(1, a, seconds(1));  // the writer made anew: due later than the samples queued
    run_for(seconds(2));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(d), repair(1), sample_of(a), sample_of(a)}))
        << "a camp drops a sample of a writer it has not heard of";
}

TEST_F(WriterAnnouncementSchedulingTest, IsSentAtTheEndOfItsWaitWhateverWaitsNeverDiscarded) {
    make_sut(PolicyKind::ttl, 10'000);
    push(d, 1'000);  // about 0.9 s on the link
    release();
    push_writer_announcement(1, c, milliseconds(300));  // its wait ends while D is on the link
    run_for(seconds(2));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(d), repair(1)}));
    EXPECT_TRUE(sink.discarded_repairs().empty());
    EXPECT_EQ(sut->repair_counters().writer_announcements_late, 1u);
}

/// A large sample's fragments after its first (Repair::Kind::continuation): the write charged the whole sample; the
/// scheduler gives the rest back and charges each fragment as it leaves, in the sample's urgency.
class ContinuationSchedulingTest : public RepairSchedulingTest {
  protected:
    /// Writes a sample of `topic` of `fragments` x FRAGMENT_BYTES as the WAN writer would: the write, then the
    /// desk's continuations (ids from 1) for every fragment after the first, numbered as sample `sample`.
    void write_large(TopicId topic, int fragments, std::uint64_t sample = 1) {  // of D
        const std::size_t payload = static_cast<std::size_t>(fragments) * FRAGMENT_PAYLOAD_BYTES;
        push(topic, payload);
        release();
        const std::uint64_t fragment_bits = 8 * config.wire.first_datagram_wire_bytes(payload);
        for (int k = 2; k <= fragments; ++k) {
            Repair continuation{next_id_++, topic, clock.now() + seconds(20), fragment_bits};  // D's TTL
            continuation.kind = Repair::Kind::continuation;
            continuation.prepaid_bits = fragment_bits;
            continuation.sample = sample;
            continuation.sample_payload_bytes = payload;
            sut->push_repair(continuation, clock.now(), sink);
        }
    }
    static constexpr std::size_t FRAGMENT_PAYLOAD_BYTES = 1'000;
    std::uint64_t next_id_ = 1;
};

TEST_F(ContinuationSchedulingTest, AMoreUrgentSampleGoesBetweenTheFragmentsOfALargeOne) {
    make_sut(PolicyKind::ttl, 20'000);
    write_large(d, 4);  // about 1.8 s of the link whole, 0.6 s a full fragment
    run_for(milliseconds(100));
    push(a);
    run_for(seconds(5));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(d), sample_of(a), repair(1), repair(2), repair(3)}));
    EXPECT_EQ(sut->counters(a).forwarded, 1u) << "on time: it waited for one fragment, not for the picture";
    EXPECT_EQ(sut->repair_counters().continuations_received, 3u);
    EXPECT_EQ(sut->repair_counters().continuations_sent, 3u);
    EXPECT_EQ(sut->repair_counters().received, 0u) << "not a repair for a reader";
}

TEST_F(ContinuationSchedulingTest, AFragmentIsChargedOnceWhenItLeaves) {
    make_sut(PolicyKind::ttl, 20'000);
    write_large(d, 4);
    const base::Duration whole =
        base::from_seconds(static_cast<double>(config.wire.wire_bits(4 * FRAGMENT_PAYLOAD_BYTES)) / 20'000.0);
    run_for(whole + milliseconds(400));  // every fragment has left, if each was charged once
    const std::size_t before = sink.departures().size();
    push(b);
    release();
    EXPECT_EQ(sink.departures().size(), before + 1) << "the link is free: nothing was charged twice";
}

TEST_F(ContinuationSchedulingTest, AFragmentWhoseSampleCanNoLongerArriveIsNotSent) {
    make_sut(PolicyKind::ttl, 10'000);
    push(d, 2 * FRAGMENT_PAYLOAD_BYTES, milliseconds(19'000));  // due in 1 s at the source
    release();
    Repair continuation{1, d, clock.now() + milliseconds(500), 8 * 1'100};
    continuation.kind = Repair::Kind::continuation;
    continuation.prepaid_bits = continuation.wire_bits;
    sut->push_repair(continuation, clock.now(), sink);
    run_for(seconds(3));
    EXPECT_EQ(sink.discarded_repairs(), (std::vector<std::uint64_t>{1}));
    EXPECT_EQ(sut->repair_counters().continuations_late, 1u);
    EXPECT_EQ(sut->repair_counters().late, 0u) << "counted apart from the readers' repairs";
}

TEST_F(ContinuationSchedulingTest, ASampleWhoseFragmentCannotArriveIsCutShortCountedDroppedAndNotSentFurther) {
    make_sut(PolicyKind::ttl, 20'000);
    write_large(d, 4, 7);
    sut->set_rate(200);  // a fragment is now 40 s of the link: the sample cannot arrive in its 20 s
    run_for(seconds(25));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(d)})) << "its first datagram only";
    EXPECT_EQ(sink.discarded_repairs(), (std::vector<std::uint64_t>{1, 2, 3}));
    using Cut = std::pair<std::uint64_t, DropReason>;
    EXPECT_EQ(sink.cut_short(), (std::vector<Cut>{{7, DropReason::doomed}})) << "once, for its three fragments";
    const TopicCounters counters = sut->counters(d);
    EXPECT_EQ(counters.forwarded, 0u) << "counted forwarded when written, it never arrived whole";
    EXPECT_EQ(counters.forwarded_payload_bytes, 0u);
    EXPECT_EQ(counters.dropped_for(DropReason::doomed), 1u);
    EXPECT_EQ(counters.received, counters.forwarded + counters.queued + counters.dropped_total());
    EXPECT_EQ(sut->repair_counters().samples_cut_short, 1u);
    EXPECT_EQ(sut->repair_counters().continuations_late, 3u);
}

TEST_F(ContinuationSchedulingTest, ASampleWhoseFragmentsAllLeaveStaysForwarded) {
    make_sut(PolicyKind::ttl, 20'000);
    write_large(d, 4, 7);
    run_for(seconds(5));
    EXPECT_TRUE(sink.cut_short().empty());
    EXPECT_EQ(sut->counters(d).forwarded, 1u);
    EXPECT_EQ(sut->repair_counters().samples_cut_short, 0u);
}

TEST_F(ContinuationSchedulingTest, AtShutdownASampleStillLeavingIsCutShortAsShutdown) {
    make_sut(PolicyKind::ttl, 20'000);
    write_large(d, 4, 7);
    sut->drain(sink, DropReason::shutdown);
    using Cut = std::pair<std::uint64_t, DropReason>;
    EXPECT_EQ(sink.cut_short(), (std::vector<Cut>{{7, DropReason::shutdown}}));
    EXPECT_EQ(sut->counters(d).dropped_for(DropReason::shutdown), 1u);
    EXPECT_EQ(sut->counters(d).forwarded, 0u);
}

TEST_F(ContinuationSchedulingTest, WithPacedFragmentsALargeSampleHoldsTheLinkForItsFirstDatagramOnly) {
    config.paced_fragments = true;
    make_sut(PolicyKind::ttl, 20'000);
    push(a);
    release();                            // A is active: nothing may hold the link much longer than 0.9 s
    push(d, 4 * FRAGMENT_PAYLOAD_BYTES);  // whole, 1.8 s of the link; its first datagram 0.6 s
    run_for(milliseconds(500));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(a), sample_of(d)}));
}

TEST_F(ContinuationSchedulingTest, WithoutPacedFragmentsALargeSampleWaitsForAFasterLink) {
    make_sut(PolicyKind::ttl, 20'000);
    push(a);
    release();
    push(d, 4 * FRAGMENT_PAYLOAD_BYTES);
    run_for(milliseconds(500));
    EXPECT_EQ(sink.departures(), (Departures{sample_of(a)})) << "the non-preemptive rule holds it back whole";
}

}  // namespace
}  // namespace tgw::core
