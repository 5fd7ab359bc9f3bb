// The scheduler in compact WAN mode: what one release step admits leaves as one bundle.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "compact/bundle_codec.hpp"
#include "core/paper_workload.hpp"
#include "core/urgency_demand.hpp"
#include "test/unit/core/scheduler_fixture.hpp"

namespace tgw::core {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

class BundleSchedulingTest : public SchedulerFixture {
  protected:
    void make_sut(double rate_bps, PolicyKind policy = PolicyKind::ttl) {
        config.bundles = BundleLimits{};
        plain_cdr_payloads = true;
        SchedulerFixture::make_sut(policy, rate_bps);
    }

    /// What a bundle of these plain-CDR payloads (all with the same source time) puts on the wire.
    std::size_t bundle_wire_bytes(std::initializer_list<std::pair<TopicId, std::size_t>> entries) const {
        std::size_t encoded = compact::BundleCodec::MAX_FRAME_BYTES;
        for (const auto& [topic, bytes] : entries) {
            encoded += compact::BundleCodec::entry_bytes(topic, 0, 0, bytes, true, false, nullptr);
        }
        return config.wire.wire_bytes(encoded + BundleLimits::DDS_ENVELOPE_BYTES);
    }

    base::Duration wire_time(std::size_t wire_bytes, double rate_bps) const {
        return base::from_seconds(8.0 * static_cast<double>(wire_bytes) / rate_bps);
    }
};

TEST_F(BundleSchedulingTest, WhatIsQueuedWhenTheLinkFreesLeavesAsOneBundleMostUrgentFirst) {
    make_sut(10'000);
    push(c, 288);
    push(b, 88);
    push(a, 64);
    release();
    ASSERT_EQ(sink.bundles().size(), 1u);
    EXPECT_EQ(sink.bundles()[0].topics, (std::vector<TopicId>{a, b, c}));
    EXPECT_EQ(sut->counters(a).forwarded + sut->counters(b).forwarded + sut->counters(c).forwarded, 3u);
}

TEST_F(BundleSchedulingTest, ChargesTheBundleOnceAtTheWireSizeOfItsEncoding) {
    make_sut(10'000);
    push(a, 64);
    push(b, 88);
    release();
    ASSERT_EQ(sink.bundles().size(), 1u);
    const std::size_t expected = bundle_wire_bytes({{a, 64}, {b, 88}});
    EXPECT_EQ(sink.bundles()[0].wire_bytes, expected);
    // One datagram's headers for both: less than the two samples sent alone.
    EXPECT_LT(expected, config.wire.wire_bytes(64) + config.wire.wire_bytes(88));
    push(c, 288);  // waits for the link
    release();
    EXPECT_EQ(sut->next_wakeup(clock.now()), clock.now() + wire_time(expected, 10'000));
    EXPECT_EQ(sut->counters(a).forwarded_wire_bytes + sut->counters(b).forwarded_wire_bytes, expected);
}

TEST_F(BundleSchedulingTest, SamplesArrivingWhileTheLinkIsBusyShareTheNextBundle) {
    make_sut(10'000);
    push(d, 600);
    release();  // D alone: the link is busy for about 0.6 s
    push(a, 64);
    push(b, 88);
    release();
    EXPECT_EQ(sink.bundles().size(), 1u);
    run_for(seconds(1));
    ASSERT_EQ(sink.bundles().size(), 2u);
    EXPECT_EQ(sink.bundles()[1].topics, (std::vector<TopicId>{a, b}));
}

TEST_F(BundleSchedulingTest, ASmallerLessUrgentSampleFillsTheRoomAMidSizedOneCouldNotTake) {
    make_sut(40'000);
    push(a, 64);
    for (int i = 0; i < 3; ++i)
        push(b, 420);  // too small to be worth chunking
    push(c, 288);
    release();
    ASSERT_GE(sink.bundles().size(), 1u);
    EXPECT_EQ(sink.bundles()[0].topics, (std::vector<TopicId>{a, b, b, c}));
    run_for(seconds(1));
    ASSERT_EQ(sink.bundles().size(), 2u);
    EXPECT_EQ(sink.bundles()[1].topics, (std::vector<TopicId>{b}));
    for (const Sample& s : sink.forwarded())
        EXPECT_FALSE(s.chunk);
}

TEST_F(BundleSchedulingTest, ALargeSampleThatDoesNotFitTheRoomLeftFillsItWithItsFirstChunk) {
    make_sut(40'000);
    push(a, 64);
    push(b, 1'250);
    push(c, 288);
    release();
    ASSERT_GE(sink.bundles().size(), 1u);
    EXPECT_EQ(sink.bundles()[0].topics, (std::vector<TopicId>{a, b}));
    // Full: the chunk took the room to the byte the encoding allows.
    EXPECT_GE(sink.bundles()[0].wire_bytes + 4, config.wire.wire_bytes(BundleLimits{}.max_encoded_bytes + 8));
    run_for(seconds(1));
    ASSERT_EQ(sink.bundles().size(), 2u);
    EXPECT_EQ(sink.bundles()[1].topics, (std::vector<TopicId>{b, c}));
    EXPECT_EQ(sut->counters(b).forwarded, 1u);
    EXPECT_TRUE(sut->counters(b).balanced());
}

TEST_F(BundleSchedulingTest, NoSampleJoinsABundleItWouldMakeAnEarlierEntryMissItsDeadline) {
    make_sut(10'000);
    // A has 300 ms left: alone it takes about 220 ms at 10,000 bit/s, with C about 460 ms.
    push(a, 64, milliseconds(700));
    push(c, 288);
    release();
    ASSERT_EQ(sink.bundles().size(), 1u);
    EXPECT_EQ(sink.bundles()[0].topics, (std::vector<TopicId>{a}));
    EXPECT_EQ(sut->queued_samples(), 1u);
}

// As in standard mode (SchedulerTest.TheStatusYields...): the status leaves in the next bundle, not in this one
// with the A that its bytes would make late.
// The bundle that goes in its place leaves it the time: a C sample that would make the status arrive more than a
// second after its birth waits for the status's bundle.
TEST_F(BundleSchedulingTest, TheStatusYieldsToTheSampleItsBundleWouldCostItsDeadline) {
    make_sut(10'000);
    const TopicId status = sut->add_topic({"status", seconds(5), true, seconds(1)});
    push(c, 64);
    release();                       // the link is busy for about 0.2 s
    push(a, 64, milliseconds(300));  // due in 0.7 s: at about 0.76 s behind the status, 0.6 s beside C
    push(status, 450);
    push(c, 288);
    run_for(seconds(2));
    ASSERT_EQ(sink.bundles().size(), 3u);
    EXPECT_EQ(sink.bundles()[1].topics, (std::vector<TopicId>{a}));
    EXPECT_EQ(sink.bundles()[2].topics, (std::vector<TopicId>{status, c}));
    EXPECT_EQ(sut->counters(a).dropped_total(), 0u);
}

TEST_F(BundleSchedulingTest, TheStatusStillTakesTheSamplesThatMakeTheirDeadlinesBesideIt) {
    make_sut(10'000);
    const TopicId status = sut->add_topic({"status", seconds(5), true, seconds(1)});
    push(c, 64);
    release();
    push(a, 64);  // due in 1 s: it makes it in the status's bundle
    push(status, 450);
    run_for(seconds(2));
    ASSERT_EQ(sink.bundles().size(), 2u);
    EXPECT_EQ(sink.bundles()[1].topics, (std::vector<TopicId>{status, a}));
}

// The status under --channel-grants at a compact robot's least share (core::least_share_bps), made as a hazard
// (TTL 1 s) is born: both must arrive in time, each in a bundle of its own if need be. At the share that counted
// each as a DDS sample of its own (7,824 bit/s here) the 720-byte status took 0.95 s of wire: it could neither
// yield (after the hazard it would arrive past its yield window) nor leave the hazard time, and 6 of 30 hazards
// expired behind it.
TEST_F(BundleSchedulingTest, AtTheLeastShareTheStatusAndAHazardBornTogetherBothArriveInTime) {
    const std::size_t status_bytes = 720;
    const TopicLoad hazards{"A", seconds(1), 10, 10, 0, 0, 0, 10 * 64};
    make_sut(least_share_bps({hazards}, status_bytes, seconds(1), {config.wire, true}));
    const TopicId status = sut->add_topic({"status", seconds(5), true, seconds(1)});
    for (int second = 0; second < 30; ++second) {
        if (second % 5 == 0) {
            push(status, status_bytes);
        }
        push(a, 64);
        run_for(seconds(1));
    }
    EXPECT_EQ(sut->counters(status).forwarded, 6u);
    EXPECT_EQ(sut->counters(a).forwarded, 30u);
}

TEST_F(BundleSchedulingTest, NoBundleHoldsTheLinkLongerThanTheMostUrgentActiveTopicAllows) {
    make_sut(10'000);
    push(a, 64);
    run_for(milliseconds(300));  // A is active, and the link free again
    for (int i = 0; i < 10; ++i)
        push(c, 288);
    release();
    ASSERT_EQ(sink.bundles().size(), 2u);
    const base::Duration a_alone = wire_time(bundle_wire_bytes({{a, 64}}), 10'000);
    const base::Duration longest = seconds(1) - a_alone;
    EXPECT_LE(wire_time(sink.bundles()[1].wire_bytes, 10'000), longest);
    EXPECT_GE(sink.bundles()[1].topics.size(), 2u);
}

TEST_F(BundleSchedulingTest, NoBundleEncodingGrowsPastTheLimit) {
    make_sut(1'000'000);
    for (int i = 0; i < 40; ++i)
        push(c, 100);
    run_for(seconds(1));
    EXPECT_EQ(sink.forwarded().size(), 40u);
    for (const auto& bundle : sink.bundles()) {
        EXPECT_LE(bundle.wire_bytes, config.wire.wire_bytes(BundleLimits{}.max_encoded_bytes + 8));
    }
    EXPECT_GE(sink.bundles().size(), 4u);
}

TEST_F(BundleSchedulingTest, ASampleLargerThanABundleLeavesInChunksThatEachFitADatagram) {
    make_sut(1'000'000);
    push(d, 6'000);
    run_for(seconds(1));
    EXPECT_EQ(sut->counters(d).forwarded, 1u);
    EXPECT_EQ(sut->queued_samples(), 0u);
    ASSERT_GE(sink.bundles().size(), 5u);
    std::vector<std::uint8_t> joined;
    for (const Sample& s : sink.forwarded()) {
        ASSERT_TRUE(s.chunk);
        EXPECT_EQ(s.chunk->total_bytes, 6'000u);
        EXPECT_EQ(s.chunk->offset, joined.size());
        joined.insert(joined.end(), s.payload.begin(), s.payload.end());
    }
    EXPECT_EQ(joined.size(), 6'000u);
    EXPECT_EQ(joined[1], 1);  // the plain CDR header leads the first chunk
    for (const auto& bundle : sink.bundles()) {
        EXPECT_LE(bundle.wire_bytes, config.wire.wire_bytes(BundleLimits{}.max_encoded_bytes + 8));
    }
    EXPECT_TRUE(sut->counters(d).balanced());
}

TEST_F(BundleSchedulingTest, UrgentSamplesTravelBetweenTheChunksOfAPicture) {
    // A 6 kB picture takes 1.2 s of a 40,000 bit/s link: sent whole it would cost a 1 s hazard its deadline.
    make_sut(40'000);
    push(c, 6'000);
    for (int i = 0; i < 15; ++i) {
        push(a, 64);
        run_for(milliseconds(200));
    }
    run_for(seconds(2));
    EXPECT_EQ(sut->counters(a).forwarded, 15u);
    EXPECT_EQ(sut->counters(c).forwarded, 1u);
    // A's samples are between the picture's chunks, each well within its TTL.
    std::size_t a_between = 0;
    bool chunk_seen = false, last_chunk_seen = false;
    for (const Sample& s : sink.forwarded()) {
        if (s.topic == c) {
            chunk_seen = true;
            last_chunk_seen = s.completes_sample();
        } else if (chunk_seen && !last_chunk_seen) {
            ++a_between;
        }
    }
    EXPECT_GE(a_between, 3u);
    EXPECT_EQ(sut->counters(a).dropped_total(), 0u);
    for (const auto& bundle : sink.bundles()) {
        EXPECT_LT(wire_time(bundle.wire_bytes, 40'000), seconds(1) - wire_time(bundle_wire_bytes({{a, 64}}), 40'000));
    }
}

TEST_F(BundleSchedulingTest, APictureWhoseChunksCannotAllArriveInTimeIsNotStarted) {
    make_sut(10'000);
    push(c, 6'000);  // 4.8 s of payload alone at 10,000 bit/s, against a TTL of 5 s
    run_for(seconds(1));
    EXPECT_EQ(sut->counters(c).dropped_for(DropReason::doomed), 1u);
    EXPECT_TRUE(sink.bundles().empty());
    ASSERT_EQ(sink.dropped().size(), 1u);
    EXPECT_EQ(sink.dropped()[0].sample.payload.size(), 6'000u);
}

TEST_F(BundleSchedulingTest, APictureIsAbandonedAsDoomedWhenTheLinkSlowsAndLoggedWhole) {
    make_sut(40'000);
    push(c, 6'000);
    run_for(milliseconds(500));
    ASSERT_FALSE(sink.forwarded().empty());
    sut->set_rate(2'000);
    run_for(seconds(6));
    EXPECT_EQ(sut->counters(c).forwarded, 0u);
    EXPECT_EQ(sut->counters(c).dropped_for(DropReason::doomed), 1u);
    EXPECT_EQ(sut->queued_samples(), 0u);
    EXPECT_TRUE(sut->counters(c).balanced());
    ASSERT_EQ(sink.dropped().size(), 1u);
    EXPECT_EQ(sink.dropped()[0].sample.payload.size(), 6'000u);
    EXPECT_FALSE(sink.dropped()[0].sample.chunk);
}

TEST_F(BundleSchedulingTest, ARefusedChunkLogsTheWholeSampleOnce) {
    make_sut(1'000'000);
    sink.refuse_writes();
    push(d, 6'000);
    run_for(seconds(1));
    EXPECT_EQ(sut->counters(d).dropped_for(DropReason::write_failed), 1u);
    ASSERT_EQ(sink.dropped().size(), 1u);
    EXPECT_EQ(sink.dropped()[0].sample.payload.size(), 6'000u);
    EXPECT_TRUE(sut->counters(d).balanced());
    EXPECT_EQ(sut->queued_samples(), 0u);
}

TEST_F(BundleSchedulingTest, ShutdownLogsAPictureStillInChunks) {
    make_sut(40'000);
    push(c, 6'000);
    run_for(milliseconds(300));
    EXPECT_EQ(sut->queued_samples(), 1u);
    sut->drain(sink);
    EXPECT_EQ(sut->counters(c).dropped_for(DropReason::shutdown), 1u);
    EXPECT_TRUE(sut->counters(c).balanced());
}

TEST_F(BundleSchedulingTest, ARefusedBundleCountsEachEntryAsWriteFailed) {
    make_sut(10'000);
    sink.refuse_writes();
    push(a, 64);
    push(b, 88);
    release();
    EXPECT_EQ(sut->counters(a).dropped_for(DropReason::write_failed), 1u);
    EXPECT_EQ(sut->counters(b).dropped_for(DropReason::write_failed), 1u);
    EXPECT_EQ(sut->counters(a).forwarded, 0u);
    EXPECT_EQ(sink.dropped_count(DropReason::write_failed), 2u);
}

TEST_F(BundleSchedulingTest, TheRoomMoreUrgentTopicsLeaveCarriesTheLeastUrgentTopicSamplesThatCanStillArrive) {
    // The paper's workload at 25,000 bit/s: A, B and C take about 22,000 of it. D's backlog reaches the head of its
    // queue only with less time left than its chunks need; the room left must go to a D that can still arrive,
    // not wait behind the one that cannot until it expires.
    make_sut(25'000);
    const std::size_t sizes[] = {paper_message_serialized_bytes(41), paper_message_serialized_bytes(66),
                                 paper_message_serialized_bytes(266), paper_message_serialized_bytes(1'016)};
    const auto publish_for = [&](base::Duration span) {
        for (base::Duration t{}; t < span; t += milliseconds(200)) {
            for (TopicId topic : {a, b, c, d})
                push(topic, sizes[topic]);
            run_for(milliseconds(200));
        }
    };
    publish_for(seconds(40));  // D's queue fills to its TTL
    const std::uint64_t d_before = sut->counters(d).forwarded;
    publish_for(seconds(40));
    // About 2,500 bit/s are left: a D every 4 s or so.
    EXPECT_GE(sut->counters(d).forwarded - d_before, 6u) << "expired " << sink.dropped_count(DropReason::expired)
                                                         << ", doomed " << sink.dropped_count(DropReason::doomed);
    for (TopicId topic : {a, b, c})
        EXPECT_EQ(sut->counters(topic).dropped_total(), 0u) << "topic " << topic;
}

// A robot at its least share (7,599 bit/s) starts a 6 kB camera topic (TTL 5 s, about 7 s of wire): the camera's
// topic became the one the non-preemptive rule protected, with a negative limit, and nothing left the gateway again
// (three robots on grants: one robot's A 38 of 200 on time).
TEST_F(BundleSchedulingTest, ACameraThatCannotMakeItsTtlAtTheRateStopsNothing) {
    make_sut(7'599);
    const TopicId status = sut->add_topic({"status", seconds(5), true, seconds(1)});
    const TopicId camera = sut->add_topic({"camera", seconds(5)});
    for (int tick = 0; tick < 200; ++tick) {  // 20 s
        if (tick % 4 == 0) {
            push(a, 64);
            push(b, 88);
        }
        if (tick % 10 == 0) {
            push(camera, 6'020);
        }
        if (tick % 50 == 0) {
            push(status, 700);
        }
        run_for(milliseconds(100));
    }
    // Not all: each status is 0.74 s of wire here, most of A's TTL, and costs an A sample now and then (43 of 50).
    EXPECT_GE(sut->counters(a).forwarded, 40u);
    EXPECT_GE(sut->counters(b).forwarded, 40u);
    EXPECT_EQ(sut->counters(status).forwarded, 4u);
}

TEST_F(BundleSchedulingTest, EverySampleIsForwardedQueuedOrLogged) {
    config.memory_cap_bytes = 40'000;
    make_sut(15'000);
    run_random_load(11, 5'000);
    for (TopicId t : {a, b, c, d}) {
        EXPECT_TRUE(sut->counters(t).balanced()) << "topic " << t;
    }
    const TopicCounters total = sut->total_counters();
    EXPECT_EQ(total.received, 5'000u);
    const auto forwarded = sink.forwarded();
    EXPECT_EQ(total.forwarded,
              static_cast<std::size_t>(std::count_if(forwarded.begin(), forwarded.end(),
                                                     [](const Sample& s) { return s.completes_sample(); })));
    EXPECT_EQ(total.dropped_total(), sink.dropped().size());
    EXPECT_GT(sink.bundles().size(), 0u);
    EXPECT_LT(sink.bundles().size(), total.forwarded);
}

}  // namespace
}  // namespace tgw::core
