// The scheduler under a topic's rules (TopicConfig::max_rate_hz, TopicConfig::latest_only): what the cap thins
// and what a newer sample replaces go to the log, as rate_capped and superseded; nothing is dropped unsaid.
#include <gtest/gtest.h>

#include "test/unit/core/scheduler_fixture.hpp"

namespace tgw::core {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

class TopicRulesSchedulingTest : public SchedulerFixture {
  protected:
    /// A sample of `topic` for `instance` (0: unkeyed), its first payload byte `value`.
    void push_instance(TopicId topic, std::uint8_t instance, std::uint8_t value, std::size_t bytes = 64) {
        Sample s;
        s.topic = topic;
        s.payload.assign(bytes, value);
        if (instance != 0) {
            s.key.valid = true;
            s.key.bytes[0] = instance;
        }
        s.source_time = clock.wall_now();
        sut->push(std::move(s), clock.now(), clock.wall_now(), sink);
    }

    /// A topic with a TTL of 2 s (5 s for a latest_only one) and the rule given.
    TopicId capped_topic(double max_rate_hz) {
        TopicConfig config{"capped", seconds(2)};
        config.max_rate_hz = max_rate_hz;
        return sut->add_topic(config);
    }
    TopicId latest_only_topic() {
        TopicConfig config{"latest", seconds(5)};
        config.latest_only = true;
        return sut->add_topic(config);
    }

    std::vector<std::uint8_t> forwarded_values(TopicId topic) const {
        std::vector<std::uint8_t> values;
        for (const Sample& s : sink.forwarded())
            if (s.topic == topic)
                values.push_back(s.payload.front());
        return values;
    }
};

TEST_F(TopicRulesSchedulingTest, ACappedTopicIsThinnedAndTheRestLoggedAsRateCapped) {
    make_sut(PolicyKind::ttl, 1e6);
    const TopicId cam = capped_topic(5.0);
    for (int i = 0; i < 60; ++i) {  // 30 Hz for 2 s
        push(cam);
        run_for(milliseconds(33));
    }
    run_for(seconds(1));
    const TopicCounters& counts = sut->counters(cam);
    EXPECT_EQ(counts.received, 60u);
    EXPECT_GE(counts.forwarded, 9u);
    EXPECT_LE(counts.forwarded, 11u);
    EXPECT_EQ(counts.dropped_for(DropReason::rate_capped), 60u - counts.forwarded);
    EXPECT_EQ(sink.dropped_count(DropReason::rate_capped), 60u - counts.forwarded);
    EXPECT_TRUE(counts.balanced());
}

TEST_F(TopicRulesSchedulingTest, TheCapThinsOnlyItsTopic) {
    make_sut(PolicyKind::ttl, 1e6);
    const TopicId cam = capped_topic(1.0);
    for (int i = 0; i < 10; ++i) {
        push(cam);
        push(a);
        run_for(milliseconds(100));
    }
    EXPECT_EQ(sut->counters(a).forwarded, 10u);
    EXPECT_EQ(sut->counters(cam).forwarded, 1u);
}

TEST_F(TopicRulesSchedulingTest, TheCapAppliesUnderFifoToo) {
    make_sut(PolicyKind::fifo, 1e6);
    const TopicId cam = capped_topic(2.0);
    for (int i = 0; i < 10; ++i) {  // 10 Hz for 1 s
        push(cam);
        clock.advance(milliseconds(100));
    }
    EXPECT_EQ(sut->counters(cam).forwarded, 2u);
    EXPECT_EQ(sut->counters(cam).dropped_for(DropReason::rate_capped), 8u);
}

TEST_F(TopicRulesSchedulingTest, ALatestOnlyTopicSendsItsLatestValueNotABacklog) {
    // 100 bytes at 2,000 bit/s: about 0.6 s of wire each (headers included), so pose samples at 10 Hz queue up.
    make_sut(PolicyKind::ttl, 2'000);
    const TopicId p = latest_only_topic();
    for (std::uint8_t i = 1; i <= 30; ++i) {
        push_instance(p, 0, i, 100);
        run_for(milliseconds(100));
    }
    run_for(seconds(3));
    const std::vector<std::uint8_t> sent = forwarded_values(p);
    ASSERT_FALSE(sent.empty());
    EXPECT_EQ(sent.back(), 30) << "the last value published reaches the camp";
    EXPECT_LE(sent.size(), 8u) << "not the backlog of 30";
    EXPECT_TRUE(std::is_sorted(sent.begin(), sent.end()));
    const TopicCounters& counts = sut->counters(p);
    EXPECT_EQ(counts.dropped_for(DropReason::superseded), 30u - sent.size());
    EXPECT_EQ(counts.queued, 0u);
    EXPECT_TRUE(counts.balanced());
}

TEST_F(TopicRulesSchedulingTest, ALatestOnlySampleReplacesOnlyItsOwnInstance) {
    make_sut(PolicyKind::ttl, 1e6);
    const TopicId j = latest_only_topic();
    sut->set_reachable(j, false);  // held: every sample stays queued until a reader matches
    push_instance(j, 1, 10);
    push_instance(j, 2, 20);
    push_instance(j, 1, 11);
    push_instance(j, 3, 30);
    push_instance(j, 2, 21);
    EXPECT_EQ(sut->counters(j).queued, 3u);
    EXPECT_EQ(sink.dropped_count(DropReason::superseded), 2u);
    sut->set_reachable(j, true);
    run_for(seconds(1));
    std::vector<std::uint8_t> sent = forwarded_values(j);
    std::sort(sent.begin(), sent.end());
    EXPECT_EQ(sent, (std::vector<std::uint8_t>{11, 21, 30}));
}

TEST_F(TopicRulesSchedulingTest, ASampleAlreadySentIsNotReplaced) {
    make_sut(PolicyKind::ttl, 1e6);
    const TopicId p = latest_only_topic();
    push_instance(p, 0, 1);
    run_for(seconds(1));
    push_instance(p, 0, 2);
    run_for(seconds(1));
    EXPECT_EQ(forwarded_values(p), (std::vector<std::uint8_t>{1, 2}));
    EXPECT_EQ(sink.dropped_count(DropReason::superseded), 0u);
}

TEST_F(TopicRulesSchedulingTest, ADisposeIsNeverReplacedAndReplacesNothing) {
    make_sut(PolicyKind::ttl, 1e6);
    const TopicId p = latest_only_topic();
    sut->set_reachable(p, false);
    push_instance(p, 1, 1);
    Sample dispose;
    dispose.topic = p;
    dispose.kind = SampleKind::dispose;
    dispose.key.valid = true;
    dispose.key.bytes[0] = 1;
    dispose.source_time = clock.wall_now();
    sut->push(std::move(dispose), clock.now(), clock.wall_now(), sink);
    push_instance(p, 1, 2);
    EXPECT_EQ(sut->counters(p).queued, 2u) << "the dispose and the newest data";
    EXPECT_EQ(sink.dropped_count(DropReason::superseded), 1u);
}

TEST_F(TopicRulesSchedulingTest, WithoutRulesEverySampleIsKept) {
    make_sut(PolicyKind::ttl, 1e6);
    sut->set_reachable(a, false);
    for (int i = 0; i < 5; ++i)
        push(a);
    EXPECT_EQ(sut->counters(a).queued, 5u);
    EXPECT_EQ(sink.dropped().size(), 0u);
}

}  // namespace
}  // namespace tgw::core
