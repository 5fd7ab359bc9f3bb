// The scheduler while no base-camp reader takes a topic (Scheduler::set_reachable): its samples wait for one
// until their deadline and are then logged as no_reader; nothing is sent to no one.
#include <gtest/gtest.h>

#include "test/unit/core/scheduler_fixture.hpp"

namespace tgw::core {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

class ReachabilityTest : public SchedulerFixture {};

TEST_F(ReachabilityTest, ATopicWithNoReaderKeepsItsSamplesUntilOneMatches) {
    make_sut(PolicyKind::ttl, 1e6);
    sut->set_reachable(a, false);
    push(a);
    run_for(milliseconds(500));
    EXPECT_TRUE(sink.forwarded().empty());
    EXPECT_EQ(sut->counters(a).queued, 1u);

    sut->set_reachable(a, true);
    release();
    EXPECT_EQ(sink.forwarded_topics(), (std::vector<TopicId>{a}));
    EXPECT_TRUE(sut->counters(a).balanced());
}

TEST_F(ReachabilityTest, SamplesStillWithoutAReaderAtTheirDeadlineAreLoggedAsNoReader) {
    make_sut(PolicyKind::ttl, 1e6);
    sut->set_reachable(a, false);
    push(a);
    push(a, 64, milliseconds(400));
    run_for(seconds(2));
    EXPECT_TRUE(sink.forwarded().empty());
    EXPECT_EQ(sink.dropped_count(DropReason::no_reader), 2u);
    EXPECT_EQ(sut->counters(a).dropped_for(DropReason::no_reader), 2u);
    EXPECT_EQ(sut->queued_samples(), 0u);
    EXPECT_TRUE(sut->counters(a).balanced());
    EXPECT_FALSE(sut->next_wakeup(clock.now()));
}

TEST_F(ReachabilityTest, OtherTopicsFlowWhileOneHasNoReader) {
    make_sut(PolicyKind::ttl, 10'000);
    sut->set_reachable(a, false);
    for (int i = 0; i < 5; ++i) {
        push(a);
        push(b);
        run_for(milliseconds(200));
    }
    EXPECT_EQ(sut->counters(b).forwarded, 5u);
    EXPECT_EQ(sut->counters(a).forwarded, 0u);
    EXPECT_EQ(sut->counters(a).queued + sut->counters(a).dropped_for(DropReason::no_reader), 5u);
}

TEST_F(ReachabilityTest, ATopicWithNoReaderDoesNotHoldBackLargerSamplesOfOthers) {
    // A (TTL 1 s) active would keep D's 2,000 bytes (1.6 s at 10,000 bit/s) off the link; unreachable, it cannot
    // send, so it protects nothing.
    make_sut(PolicyKind::ttl, 10'000);
    push(a);
    run_for(milliseconds(100));
    sut->set_reachable(a, false);
    push(a);
    push(d, 2'000);
    run_for(milliseconds(100));
    EXPECT_EQ(sut->counters(d).forwarded, 1u);
}

TEST_F(ReachabilityTest, AReaderLostAgainParksWhatIsQueued) {
    make_sut(PolicyKind::ttl, 1e6);
    sut->set_reachable(c, false);
    push(c);
    sut->set_reachable(c, true);
    sut->set_reachable(c, false);
    run_for(seconds(6));
    EXPECT_EQ(sink.dropped_count(DropReason::no_reader), 1u);
}

TEST_F(ReachabilityTest, UnderFifoASampleWithNoReaderIsLoggedAtOnce) {
    make_sut(PolicyKind::fifo, 1e6);
    sut->set_reachable(a, false);
    push(a);
    EXPECT_TRUE(sink.forwarded().empty());
    EXPECT_EQ(sink.dropped_count(DropReason::no_reader), 1u);
}

TEST_F(ReachabilityTest, ShutdownLogsSamplesThatWaitedForAReader) {
    make_sut(PolicyKind::ttl, 1e6);
    sut->set_reachable(a, false);
    push(a);
    push(b);
    release();
    sut->drain(sink);
    EXPECT_EQ(sink.dropped_count(DropReason::shutdown), 1u);
    EXPECT_EQ(sut->queued_samples(), 0u);
}

TEST_F(ReachabilityTest, BundlesLeaveOutTopicsWithNoReader) {
    config.bundles = BundleLimits{};
    plain_cdr_payloads = true;
    make_sut(PolicyKind::ttl, 1e6);
    sut->set_reachable(b, false);
    push(a);
    push(b);
    push(c);
    release();
    ASSERT_EQ(sink.bundles().size(), 1u);
    EXPECT_EQ(sink.bundles()[0].topics, (std::vector<TopicId>{a, c}));
    EXPECT_EQ(sut->counters(b).queued, 1u);
}

}  // namespace
}  // namespace tgw::core
