#include "gateway/core/deadline_queue.hpp"

#include <gtest/gtest.h>

namespace tgw::core {
namespace {

class DeadlineQueueTest : public ::testing::Test {
  protected:
    Sample make(TopicId topic, int deadline_ms, std::uint64_t sequence, std::size_t bytes = 10) {
        Sample s;
        s.topic = topic;
        s.payload.assign(bytes, 0xab);
        s.deadline = SteadyTime(std::chrono::milliseconds(deadline_ms));
        s.sequence = sequence;
        return s;
    }
    DeadlineQueue sut;
};

TEST_F(DeadlineQueueTest, OrdersByRankThenDeadlineThenArrival) {
    sut.push(make(0, 500, 0), 2);
    sut.push(make(1, 900, 1), 1);
    sut.push(make(2, 100, 2), 2);
    sut.push(make(3, 900, 3), 1);

    std::vector<TopicId> order;
    while (!sut.empty())
        order.push_back(sut.take(sut.most_urgent()).topic);

    EXPECT_EQ(order, (std::vector<TopicId>{1, 3, 2, 0}));
}

TEST_F(DeadlineQueueTest, EarliestDeadlineIgnoresRank) {
    sut.push(make(0, 500, 0), 1);
    sut.push(make(1, 100, 1), 9);

    EXPECT_EQ(sut.at(sut.earliest_deadline()).topic, 1u);
    EXPECT_EQ(sut.at(sut.most_urgent()).topic, 0u);
    EXPECT_EQ(sut.at(sut.least_urgent()).topic, 1u);
}

TEST_F(DeadlineQueueTest, CountsPayloadAndBookkeepingBytes) {
    sut.push(make(0, 1, 0, 100), 0);
    sut.push(make(0, 2, 1, 50), 0);
    EXPECT_EQ(sut.memory_bytes(), 150 + 2 * DeadlineQueue::BOOKKEEPING_BYTES);

    sut.take(sut.most_urgent());
    EXPECT_EQ(sut.memory_bytes(), 50 + DeadlineQueue::BOOKKEEPING_BYTES);
}

TEST_F(DeadlineQueueTest, ReusesSlotsOfTakenSamples) {
    for (int round = 0; round < 3; ++round) {
        sut.push(make(0, 10, 2 * round), 0);
        sut.push(make(1, 20, 2 * round + 1), 0);
        EXPECT_EQ(sut.take(sut.most_urgent()).topic, 0u);
        EXPECT_EQ(sut.take(sut.most_urgent()).topic, 1u);
    }
    EXPECT_TRUE(sut.empty());
    EXPECT_EQ(sut.memory_bytes(), 0u);
}

TEST_F(DeadlineQueueTest, TakeHandsOverThePayload) {
    sut.push(make(7, 10, 0, 3), 0);
    Sample s = sut.take(sut.most_urgent());
    EXPECT_EQ(s.topic, 7u);
    EXPECT_EQ(s.payload, (std::vector<std::uint8_t>{0xab, 0xab, 0xab}));
}

}  // namespace
}  // namespace tgw::core
