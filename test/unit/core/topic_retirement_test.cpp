// Topics that come and go (Scheduler::retire_topic): a topic is forgotten only once nothing of it is queued, its
// counts stay in the totals, and its slot is taken again, so the per-topic tables do not grow with churn.
#include <gtest/gtest.h>

#include "test/unit/core/scheduler_fixture.hpp"

namespace tgw::core {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

class TopicRetirementTest : public SchedulerFixture {};

TEST_F(TopicRetirementTest, ATopicWithSamplesQueuedIsNotRetired) {
    make_sut(PolicyKind::ttl, 1e6);
    sut->set_reachable(a, false);
    push(a);
    EXPECT_FALSE(sut->retire_topic(a, true));
    EXPECT_FALSE(sut->retired(a));
    EXPECT_EQ(sut->live_topics(), 4u);
}

TEST_F(TopicRetirementTest, ARetiredTopicsCountsStayInTheTotals) {
    make_sut(PolicyKind::ttl, 1e6);
    push(a);
    push(a);
    run_for(milliseconds(100));
    const TopicCounters before = sut->total_counters();
    const auto final_counts = sut->retire_topic(a, true);
    ASSERT_TRUE(final_counts);
    EXPECT_EQ(final_counts->received, 2u);
    EXPECT_EQ(final_counts->forwarded, 2u);
    EXPECT_TRUE(final_counts->balanced());
    EXPECT_EQ(sut->total_counters().received, before.received);
    EXPECT_EQ(sut->total_counters().forwarded, before.forwarded);
    EXPECT_EQ(sut->retired_counters().received, 2u);
    EXPECT_TRUE(sut->retired(a));
    EXPECT_EQ(sut->live_topics(), 3u);
}

TEST_F(TopicRetirementTest, ATopicWhoseSamplesExpiredIsRetiredOnceTheyAreLogged) {
    make_sut(PolicyKind::ttl, 1e6);
    sut->set_reachable(a, false);
    push(a);
    run_for(seconds(2));
    EXPECT_EQ(sut->counters(a).dropped_for(DropReason::no_reader), 1u);
    const auto final_counts = sut->retire_topic(a, true);
    ASSERT_TRUE(final_counts);
    EXPECT_EQ(final_counts->dropped_for(DropReason::no_reader), 1u);
    EXPECT_TRUE(final_counts->balanced());
}

TEST_F(TopicRetirementTest, ANewTopicTakesARetiredSlotWithFreshCounts) {
    make_sut(PolicyKind::ttl, 1e6);
    push(b);
    run_for(milliseconds(100));
    ASSERT_TRUE(sut->retire_topic(b, true));
    const TopicId next = sut->add_topic({"E", milliseconds(500)});
    EXPECT_EQ(next, b);
    EXPECT_EQ(sut->topic_count(), 4u);
    EXPECT_EQ(sut->topic(next).name, "E");
    EXPECT_EQ(sut->counters(next).received, 0u);
    push(next);
    run_for(milliseconds(100));
    EXPECT_EQ(sut->counters(next).forwarded, 1u);
    EXPECT_EQ(sut->total_counters().forwarded, 2u);
}

TEST_F(TopicRetirementTest, ChurnDoesNotGrowTheTopicTable) {
    make_sut(PolicyKind::ttl, 1e6);
    for (int i = 0; i < 1000; ++i) {
        const TopicId t = sut->add_topic({"churn", milliseconds(200)});
        push(t);
        run_for(milliseconds(100));
        ASSERT_TRUE(sut->retire_topic(t, true));
    }
    EXPECT_EQ(sut->topic_count(), 5u);
    EXPECT_EQ(sut->live_topics(), 4u);
    EXPECT_EQ(sut->total_counters().forwarded, 1000u);
    EXPECT_TRUE(sut->total_counters().balanced());
}

TEST_F(TopicRetirementTest, ASlotNotReusableIsTakenOnlyWhenAskedForByItsId) {
    make_sut(PolicyKind::ttl, 1e6);
    ASSERT_TRUE(sut->retire_topic(c, false));
    const TopicId other = sut->add_topic({"E", seconds(1)});
    EXPECT_NE(other, c);
    EXPECT_FALSE(sut->add_topic_at(a, {"A", seconds(1)})) << "A is not retired";
    EXPECT_TRUE(sut->add_topic_at(c, {"C", seconds(5)}));
    EXPECT_FALSE(sut->retired(c));
    push(c);
    run_for(milliseconds(100));
    EXPECT_EQ(sut->counters(c).forwarded, 1u);
}

TEST_F(TopicRetirementTest, ARetiredTopicThatWasParkedLeavesNothingParked) {
    make_sut(PolicyKind::ttl, 1e6);
    sut->set_reachable(a, false);
    ASSERT_TRUE(sut->retire_topic(a, true));
    const TopicId again = sut->add_topic({"A2", seconds(1)});
    ASSERT_EQ(again, a);
    push(again);
    run_for(milliseconds(100));
    EXPECT_EQ(sut->counters(again).forwarded, 1u) << "the new topic in the slot starts reachable";
}

}  // namespace
}  // namespace tgw::core
