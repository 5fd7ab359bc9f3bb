// The Scheduler's rules that stand on their own: the non-preemptive rule's protected topics, the paper's filter,
// the link's reserve and the chunk plans. The Scheduler's own tests cover them at work together.
#include <gtest/gtest.h>

#include <vector>

#include "core/chunk_planning.hpp"
#include "core/link_reserve.hpp"
#include "core/paper_filter.hpp"
#include "core/protected_topics.hpp"

namespace tgw::core {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

base::SteadyTime at(int ms) {
    return base::SteadyTime(milliseconds(ms));
}

ProtectedTopics::Guard guard(TopicId topic, int limit_ms, std::int64_t rank) {
    return {topic, milliseconds(limit_ms), rank};
}

TEST(ProtectedTopicsTest, KeepsTheTwoTopicsWithTheLeastRoom) {
    ProtectedTopics p;
    p.offer(guard(0, 900, 1000));
    p.offer(guard(1, 300, 5000));
    p.offer(guard(2, 600, 2000));
    EXPECT_EQ(p.first().topic, 1u);
    EXPECT_EQ(p.second().topic, 2u);
}

TEST(ProtectedTopicsTest, ATopicWithoutRoomProtectsNoOne) {
    ProtectedTopics p;
    p.offer(guard(0, 0, 1000));
    EXPECT_EQ(p.first().topic, ProtectedTopics::NONE);
    EXPECT_EQ(p.limit_for(1, 2000), base::Duration::max());
}

TEST(ProtectedTopicsTest, ASampleIsBoundByTheLeastRoomOfTheTopicsNoLessUrgentThanItsOwnItselfAside) {
    ProtectedTopics p;
    p.offer(guard(0, 400, 1000));  // the most urgent topic, least room
    p.offer(guard(1, 800, 2000));
    EXPECT_EQ(p.limit_for(2, 5000), milliseconds(400));
    EXPECT_EQ(p.limit_for(0, 1000), base::Duration::max()) << "topic 1 is less urgent than topic 0";
    EXPECT_EQ(p.limit_for(0, 5000), milliseconds(800)) << "its own room does not bound it";
    EXPECT_EQ(p.limit_for(3, 500), base::Duration::max()) << "nothing protected is as urgent";
}

TEST(ProtectedTopicsTest, AnUpdateThatLeavesTheSecondUnknownAsksForARebuild) {
    ProtectedTopics p;
    p.offer(guard(0, 300, 1000));
    p.offer(guard(1, 500, 2000));
    EXPECT_TRUE(p.update(guard(1, 200, 2000)));
    EXPECT_EQ(p.first().topic, 1u) << "the second overtook the first";
    EXPECT_EQ(p.second().topic, 0u);
    EXPECT_FALSE(p.update(guard(1, 900, 2000))) << "a third topic may now have less room than it";
    EXPECT_FALSE(p.update(guard(0, 0, 1000))) << "one of the two leaves";
}

class PaperFilterTest : public ::testing::Test {
  protected:
    void push(TopicId topic, std::size_t bytes, std::int64_t rank) {
        Sample s;
        s.topic = topic;
        s.payload.assign(bytes, 0);
        s.deadline = at(10'000);
        s.sequence = next_sequence_++;
        queue_.push(std::move(s), rank);
    }
    std::vector<TopicId> topics_of(const std::vector<DeadlineQueue::Slot>& slots) {
        std::vector<TopicId> topics;
        for (const DeadlineQueue::Slot slot : slots)
            topics.push_back(queue_.at(slot).topic);
        return topics;
    }
    DeadlineQueue queue_;
    std::uint64_t next_sequence_ = 0;
};

TEST_F(PaperFilterTest, MarksByTtlWhatFitsTheRateTimesThePeriodCountingPayloadAndTheAssumedOverhead) {
    PaperFilter filter(seconds(1), 0.25);
    push(0, 100, 1000);   // 1,000 bits with the overhead
    push(3, 400, 20000);  // 4,000
    push(1, 200, 2000);   // 2,000
    push(2, 100, 5000);   // 1,000
    // 4,500 bits a period: topics 0, 1 and 2 by their TTLs (4,000 bits in all); 3 (4,000 more) waits.
    const auto marked = filter.run(at(0), queue_, 4500);
    ASSERT_TRUE(marked.has_value());
    EXPECT_EQ(topics_of(*marked), (std::vector<TopicId>{0, 1, 2}));
}

TEST_F(PaperFilterTest, RunsOnceAPeriodAndARunThatCameLateStartsThePeriodsAnew) {
    PaperFilter filter(seconds(1), 0.0);
    EXPECT_EQ(filter.next_period(at(50)), at(50)) << "before its first run, now";
    EXPECT_TRUE(filter.run(at(100), queue_, 1000).has_value());
    EXPECT_FALSE(filter.run(at(600), queue_, 1000).has_value());
    EXPECT_EQ(filter.next_period(at(600)), at(1100));
    EXPECT_TRUE(filter.run(at(1100), queue_, 1000).has_value());
    EXPECT_TRUE(filter.run(at(5000), queue_, 1000).has_value());
    EXPECT_EQ(filter.next_period(at(5000)), at(6000));
}

TEST(LinkReserveTest, CoversWhatItSavedUpToAWindowsWorth) {
    LinkReserve reserve(seconds(2));
    EXPECT_EQ(reserve.uncovered(at(0), 1000, 500.0), 1000u) << "nothing saved yet";
    EXPECT_EQ(reserve.uncovered(at(1000), 300, 500.0), 0u) << "500 bits saved in a second";
    EXPECT_EQ(reserve.uncovered(at(1000), 300, 500.0), 100u) << "200 left";
    EXPECT_EQ(reserve.uncovered(at(11'000), 1500, 500.0), 500u) << "ten seconds save two seconds' worth only";
}

class ChunkPlanningTest : public ::testing::Test {
  protected:
    ChunkPlanningTest() : limits_{BundleLimits::one_datagram(wire_)}, planning_(wire_, limits_, milliseconds(10)) {}
    WireModel wire_;
    BundleLimits limits_;
    ChunkPlanning planning_;
};

TEST_F(ChunkPlanningTest, AChunkedSampleCostsItsPayloadAndABundlesHeadersPerChunk) {
    const std::uint64_t one = planning_.chunk_bits(100);
    const std::uint64_t three = planning_.chunk_bits(2 * limits_.max_encoded_bytes + 100);
    EXPECT_GT(one, 800u);
    EXPECT_EQ(three - 8u * (2 * limits_.max_encoded_bytes + 100), 3 * (one - 800u)) << "three chunks' headers";
}

TEST_F(ChunkPlanningTest, NoRateLeftMeansTheChunksNeverArrive) {
    const LinkBudget budget(10'000, milliseconds(2));
    EXPECT_EQ(planning_.chunks_arrive_by(5000, at(0), 0.0, budget), base::SteadyTime::max());
    const base::SteadyTime fast = planning_.chunks_arrive_by(5000, at(0), 20'000, budget);
    const base::SteadyTime slow = planning_.chunks_arrive_by(5000, at(0), 10'000, budget);
    EXPECT_LT(fast, slow) << "the more rate the more urgent topics leave, the sooner";
}

TEST_F(ChunkPlanningTest, TwoBundlesBoundWhatMayFillARoomLeft) {
    EXPECT_TRUE(planning_.fits_two_bundles(limits_.max_encoded_bytes));
    EXPECT_FALSE(planning_.fits_two_bundles(2 * limits_.max_encoded_bytes));
    const LinkBudget budget(10'000, milliseconds(2));
    EXPECT_FALSE(planning_.arrives_in_two_bundles(at(100), at(0), budget)) << "two full bundles take about 2 s";
    EXPECT_TRUE(planning_.arrives_in_two_bundles(at(5000), at(0), budget));
}

TEST_F(ChunkPlanningTest, AChunkIsItsSliceOfTheSampleWithTheSamplesIdentity) {
    Sample whole;
    whole.topic = 7;
    whole.sequence = 42;
    whole.deadline = at(900);
    for (int i = 0; i < 100; ++i)
        whole.payload.push_back(static_cast<std::uint8_t>(i));
    const Sample::Chunk info{3, 100, 40};
    const Sample chunk = ChunkPlanning::chunk_of(whole, info, 25);
    EXPECT_EQ(chunk.topic, 7u);
    EXPECT_EQ(chunk.sequence, 42u);
    EXPECT_EQ(chunk.deadline, at(900));
    ASSERT_EQ(chunk.payload.size(), 25u);
    EXPECT_EQ(chunk.payload.front(), 40);
    EXPECT_EQ(chunk.payload.back(), 64);
    ASSERT_TRUE(chunk.chunk.has_value());
    EXPECT_EQ(chunk.chunk->offset, 40u);
    EXPECT_FALSE(chunk.completes_sample());
}

}  // namespace
}  // namespace tgw::core
