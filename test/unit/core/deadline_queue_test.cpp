#include "core/deadline_queue.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>

namespace tgw::core {
namespace {

class DeadlineQueueTest : public ::testing::Test {
  protected:
    Sample make(TopicId topic, int deadline_ms, std::uint64_t sequence, std::size_t bytes = 10) {
        Sample s;
        s.topic = topic;
        s.payload.assign(bytes, 0xab);
        s.deadline = base::SteadyTime(std::chrono::milliseconds(deadline_ms));
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

TEST_F(DeadlineQueueTest, AParkedTopicIsLeftOutOfTheUrgencyOrderButNotOutOfExpiry) {
    sut.push(make(0, 900, 0), 1);
    sut.push(make(1, 100, 1), 1);
    sut.park(1, true);
    sut.push(make(1, 200, 2), 1);  // pushed while parked
    EXPECT_EQ(sut.at(sut.most_urgent()).topic, 0u);
    std::vector<TopicId> visited;
    sut.visit_by_urgency([&](DeadlineQueue::Slot slot) {
        visited.push_back(sut.at(slot).topic);
        return true;
    });
    EXPECT_EQ(visited, (std::vector<TopicId>{0}));
    EXPECT_EQ(sut.at(sut.earliest_deadline()).topic, 1u);
    EXPECT_EQ(sut.size(), 3u);

    sut.park(1, false);
    std::vector<TopicId> order;
    while (!sut.empty())
        order.push_back(sut.take(sut.most_urgent()).topic);
    EXPECT_EQ(order, (std::vector<TopicId>{1, 1, 0}));
}

TEST_F(DeadlineQueueTest, TakingAParkedTopicsHeadKeepsItParked) {
    sut.park(0, true);
    sut.push(make(0, 100, 0), 1);
    sut.push(make(0, 200, 1), 1);
    sut.push(make(1, 900, 2), 1);
    EXPECT_EQ(sut.take(sut.earliest_deadline()).sequence, 0u);
    EXPECT_EQ(sut.at(sut.most_urgent()).topic, 1u);
    EXPECT_TRUE(sut.parked(0));
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

TEST_F(DeadlineQueueTest, KeepsTheRouteAndKindOfASampleThroughASlotsReuse) {
    sut.push(make(0, 10, 0), 0);
    sut.take(sut.most_urgent());  // the slot goes back to the free list
    Sample dispose = make(0, 10, 1, 0);
    dispose.route = 3;
    dispose.kind = SampleKind::dispose;
    sut.push(std::move(dispose), 0);
    const Sample s = sut.take(sut.most_urgent());
    EXPECT_EQ(s.route, 3u);
    EXPECT_EQ(s.kind, SampleKind::dispose);
}

TEST_F(DeadlineQueueTest, PlacesAnOutOfOrderSampleOfATopicByItsDeadline) {
    sut.push(make(0, 100, 0), 1);
    sut.push(make(0, 300, 1), 1);
    sut.push(make(0, 200, 2), 1);  // late arrival, earlier deadline
    sut.push(make(0, 50, 3), 1);   // earlier than the whole topic

    std::vector<std::uint64_t> order;
    while (!sut.empty())
        order.push_back(sut.take(sut.most_urgent()).sequence);

    EXPECT_EQ(order, (std::vector<std::uint64_t>{3, 0, 2, 1}));
}

TEST_F(DeadlineQueueTest, KeepsSamplesOfOneTopicWithDifferentRanksApart) {
    // A topic whose TTL changed while samples were queued: the old ones keep their rank.
    sut.push(make(0, 100, 0), 5);
    sut.push(make(0, 200, 1), 1);
    sut.push(make(1, 150, 2), 3);

    std::vector<std::uint64_t> order;
    while (!sut.empty())
        order.push_back(sut.take(sut.most_urgent()).sequence);

    EXPECT_EQ(order, (std::vector<std::uint64_t>{1, 2, 0}));
}

TEST_F(DeadlineQueueTest, InterleavesManyTopicsOfEqualRankByDeadline) {
    std::uint64_t seq = 0;
    for (int round = 0; round < 5; ++round)
        for (TopicId t = 0; t < 1'000; ++t)
            sut.push(make(t, 10'000 * round + static_cast<int>((t * 7919) % 1'000), seq++), 0);

    std::int64_t last = -1;
    std::size_t count = 0;
    while (!sut.empty()) {
        const Sample s = sut.take(sut.most_urgent());
        const std::int64_t d = s.deadline.time_since_epoch().count();
        EXPECT_LE(last, d);
        last = d;
        ++count;
    }
    EXPECT_EQ(count, 5'000u);
}

TEST_F(DeadlineQueueTest, LeastUrgentIsTheLastSampleOfTheLeastUrgentTopic) {
    sut.push(make(0, 100, 0), 1);
    sut.push(make(0, 900, 1), 1);
    sut.push(make(1, 50, 2), 2);
    sut.push(make(1, 60, 3), 2);
    sut.push(make(2, 1'000, 4), 1);

    EXPECT_EQ(sut.at(sut.least_urgent()).topic, 1u);
    EXPECT_EQ(sut.take(sut.least_urgent()).sequence, 3u);
    EXPECT_EQ(sut.take(sut.least_urgent()).sequence, 2u);
    EXPECT_EQ(sut.take(sut.least_urgent()).sequence, 4u);
    EXPECT_EQ(sut.take(sut.least_urgent()).sequence, 1u);
}

TEST_F(DeadlineQueueTest, EarliestDeadlineIsFoundAcrossTopicsOfAnyRank) {
    sut.push(make(0, 300, 0), 1);
    sut.push(make(1, 200, 1), 5);
    sut.push(make(2, 250, 2), 3);
    sut.push(make(1, 400, 3), 5);

    EXPECT_EQ(sut.at(sut.earliest_deadline()).topic, 1u);
    EXPECT_EQ(sut.take(sut.earliest_deadline()).sequence, 1u);
    EXPECT_EQ(sut.take(sut.earliest_deadline()).sequence, 2u);
    EXPECT_EQ(sut.take(sut.earliest_deadline()).sequence, 0u);
    EXPECT_EQ(sut.take(sut.earliest_deadline()).sequence, 3u);
}

TEST_F(DeadlineQueueTest, TakingFromTheMiddleOfATopicKeepsTheRestInOrder) {
    std::vector<DeadlineQueue::Slot> slots;
    for (int i = 0; i < 10; ++i)
        sut.push(make(0, 100 * (i + 1), static_cast<std::uint64_t>(i)), 0);
    sut.visit_by_urgency([&](DeadlineQueue::Slot slot) {
        slots.push_back(slot);
        return true;
    });
    ASSERT_EQ(slots.size(), 10u);

    EXPECT_EQ(sut.take(slots[4]).sequence, 4u);
    EXPECT_EQ(sut.take(slots[5]).sequence, 5u);
    EXPECT_EQ(sut.take(slots[9]).sequence, 9u);
    EXPECT_EQ(sut.memory_bytes(), 7 * (10 + DeadlineQueue::BOOKKEEPING_BYTES));
    sut.push(make(0, 550, 10), 0);  // lands where the taken ones were

    std::vector<std::uint64_t> order;
    while (!sut.empty())
        order.push_back(sut.take(sut.most_urgent()).sequence);
    EXPECT_EQ(order, (std::vector<std::uint64_t>{0, 1, 2, 3, 10, 6, 7, 8}));
}

TEST_F(DeadlineQueueTest, PlacesALateSampleNearTheFrontOfALongTopic) {
    for (int i = 0; i < 20; ++i)
        sut.push(make(0, 100 * (i + 1), static_cast<std::uint64_t>(i)), 0);
    sut.push(make(0, 250, 20), 0);
    sut.push(make(0, 1'950, 21), 0);

    std::vector<std::uint64_t> order;
    while (!sut.empty())
        order.push_back(sut.take(sut.least_urgent()).sequence);
    std::reverse(order.begin(), order.end());

    std::vector<std::uint64_t> expected{0, 1, 20};
    for (std::uint64_t i = 2; i < 19; ++i)
        expected.push_back(i);
    expected.push_back(21);
    expected.push_back(19);
    EXPECT_EQ(order, expected);
}

TEST_F(DeadlineQueueTest, ManyTakesFromTheMiddleLeaveTheOrderIntact) {
    for (int i = 0; i < 1'000; ++i)
        sut.push(make(static_cast<TopicId>(i % 2), i, static_cast<std::uint64_t>(i)), 0);
    std::vector<DeadlineQueue::Slot> slots;
    sut.visit_by_urgency([&](DeadlineQueue::Slot slot) {
        slots.push_back(slot);
        return true;
    });
    ASSERT_EQ(slots.size(), 1'000u);
    for (std::size_t i = 1; i < 999; ++i) {
        if (i % 10 != 0) {
            EXPECT_EQ(sut.take(slots[i]).sequence, i);
        }
    }

    std::vector<std::uint64_t> order;
    while (!sut.empty())
        order.push_back(sut.take(sut.most_urgent()).sequence);
    std::vector<std::uint64_t> expected{0};
    for (std::uint64_t i = 10; i < 999; i += 10)
        expected.push_back(i);
    expected.push_back(999);
    EXPECT_EQ(order, expected);
}

TEST_F(DeadlineQueueTest, VisitWalksInUrgencyOrderAndMayTakeTheVisitedSample) {
    sut.push(make(0, 500, 0), 2);
    sut.push(make(1, 900, 1), 1);
    sut.push(make(2, 100, 2), 2);
    sut.push(make(1, 950, 3), 1);
    sut.push(make(0, 600, 4), 2);

    std::vector<std::uint64_t> visited;
    std::vector<std::uint64_t> taken;
    sut.visit_by_urgency([&](DeadlineQueue::Slot slot) {
        const auto peek = sut.at(slot);
        visited.push_back(peek.sequence);
        if (peek.topic != 0)
            taken.push_back(sut.take(slot).sequence);
        return true;
    });
    EXPECT_EQ(visited, (std::vector<std::uint64_t>{1, 3, 2, 0, 4}));
    EXPECT_EQ(taken, (std::vector<std::uint64_t>{1, 3, 2}));
    EXPECT_EQ(sut.size(), 2u);
    EXPECT_EQ(sut.take(sut.most_urgent()).sequence, 0u);
}

TEST_F(DeadlineQueueTest, VisitStopsWhenTheVisitorSaysSo) {
    for (int i = 0; i < 5; ++i)
        sut.push(make(static_cast<TopicId>(i), 100 + i, static_cast<std::uint64_t>(i)), 0);
    int visits = 0;
    sut.visit_by_urgency([&](DeadlineQueue::Slot slot) {
        ++visits;
        sut.take(slot);
        return visits < 2;
    });
    EXPECT_EQ(visits, 2);
    EXPECT_EQ(sut.size(), 3u);
    EXPECT_EQ(sut.at(sut.most_urgent()).sequence, 2u);
}

TEST_F(DeadlineQueueTest, TakeHandsBackEveryFieldOfTheSample) {
    Sample s = make(3, 700, 42, 5);
    s.key.valid = true;
    s.key.bytes[0] = 9;
    s.key.bytes[15] = 7;
    s.source_time = base::WallTime(std::chrono::nanoseconds(123'456'789));
    s.arrival = base::SteadyTime(std::chrono::nanoseconds(987'654'321));
    sut.push(Sample(s), 4);

    const Sample out = sut.take(sut.most_urgent());
    EXPECT_EQ(out.topic, s.topic);
    EXPECT_EQ(out.payload, s.payload);
    EXPECT_EQ(out.key.bytes, s.key.bytes);
    EXPECT_EQ(out.key.valid, s.key.valid);
    EXPECT_EQ(out.source_time, s.source_time);
    EXPECT_EQ(out.arrival, s.arrival);
    EXPECT_EQ(out.deadline, s.deadline);
    EXPECT_EQ(out.sequence, s.sequence);
}

TEST_F(DeadlineQueueTest, KeepsBookkeepingUnderOneHundredBytesPerSample) {
    EXPECT_LT(DeadlineQueue::BOOKKEEPING_BYTES, 100u);
}

// Random pushes (some out of order within a topic, some ranks changing) and takes from both ends, by deadline
// and from the middle, checked against a plain sorted list.
TEST_F(DeadlineQueueTest, AgreesWithASortedListUnderRandomOperations) {
    struct Ref {
        std::int64_t rank;
        int deadline_ms;
        std::uint64_t sequence;
        TopicId topic;
        bool operator<(const Ref& o) const {
            return std::tie(rank, deadline_ms, sequence) < std::tie(o.rank, o.deadline_ms, o.sequence);
        }
    };
    std::mt19937 rng(12345);
    constexpr TopicId TOPICS = 17;
    std::vector<std::int64_t> rank_of(TOPICS);
    std::vector<int> last_deadline(TOPICS, 1'000);
    for (TopicId t = 0; t < TOPICS; ++t)
        rank_of[t] = static_cast<std::int64_t>(rng() % 4);
    std::vector<Ref> ref;
    std::uint64_t seq = 0;
    const auto deadline_of = [](const Ref& r) { return r.deadline_ms; };
    const auto ref_slot_order = [&] {
        std::vector<DeadlineQueue::Slot> slots;
        sut.visit_by_urgency([&](DeadlineQueue::Slot slot) {
            slots.push_back(slot);
            return true;
        });
        return slots;
    };
    const auto take_ref = [&](std::uint64_t sequence) {
        const auto it = std::find_if(ref.begin(), ref.end(), [&](const Ref& r) { return r.sequence == sequence; });
        ASSERT_NE(it, ref.end());
        ref.erase(it);
    };

    for (int step = 0; step < 30'000; ++step) {
        // The queue grows for the first two thirds (long lanes, tombstones) and shrinks in the last third.
        const unsigned op = rng() % 100;
        const unsigned push_share = step < 20'000 ? 62 : 40;
        if (op < push_share || ref.empty()) {
            const TopicId t = rng() % TOPICS;
            if (rng() % 200 == 0)
                rank_of[t] = static_cast<std::int64_t>(rng() % 4);
            int d = last_deadline[t] + static_cast<int>(rng() % 20);
            if (rng() % 10 == 0)
                d -= static_cast<int>(rng() % 200);  // out of order
            last_deadline[t] = std::max(last_deadline[t], d);
            sut.push(make(t, d, seq), rank_of[t]);
            ref.push_back(Ref{rank_of[t], d, seq, t});
            ++seq;
        } else if (op < 70) {
            const auto expected = std::min_element(ref.begin(), ref.end());
            ASSERT_EQ(sut.at(sut.most_urgent()).sequence, expected->sequence);
            EXPECT_EQ(sut.take(sut.most_urgent()).sequence, expected->sequence);
            ref.erase(expected);
        } else if (op < 76) {
            const auto expected = std::max_element(ref.begin(), ref.end());
            ASSERT_EQ(sut.take(sut.least_urgent()).sequence, expected->sequence);
            ref.erase(expected);
        } else if (op < 82) {
            const auto expected = std::min_element(ref.begin(), ref.end(), [&](const Ref& a, const Ref& b) {
                return std::make_pair(deadline_of(a), a.sequence) < std::make_pair(deadline_of(b), b.sequence);
            });
            ASSERT_EQ(sut.take(sut.earliest_deadline()).sequence, expected->sequence);
            ref.erase(expected);
        } else if (op < 97) {
            // Take a random sample from anywhere.
            const auto slots = ref_slot_order();
            ASSERT_EQ(slots.size(), ref.size());
            const Sample s = sut.take(slots[rng() % slots.size()]);
            take_ref(s.sequence);
        } else {
            // Walk the whole queue, taking some of the samples on the way, as the release loop does.
            std::sort(ref.begin(), ref.end());
            std::vector<std::uint64_t> visited;
            std::vector<std::uint64_t> taken;
            sut.visit_by_urgency([&](DeadlineQueue::Slot slot) {
                const auto peek = sut.at(slot);
                visited.push_back(peek.sequence);
                EXPECT_EQ(peek.deadline,
                          base::SteadyTime(std::chrono::milliseconds(ref[visited.size() - 1].deadline_ms)));
                if (rng() % 200 == 0)
                    taken.push_back(sut.take(slot).sequence);
                return true;
            });
            ASSERT_EQ(visited.size(), ref.size());
            for (std::size_t i = 0; i < ref.size(); ++i)
                ASSERT_EQ(visited[i], ref[i].sequence) << "at " << i;
            for (std::uint64_t s : taken)
                take_ref(s);
        }
        ASSERT_EQ(sut.size(), ref.size());
        ASSERT_EQ(sut.memory_bytes(), ref.size() * (10 + DeadlineQueue::BOOKKEEPING_BYTES));
    }
}

}  // namespace
}  // namespace tgw::core
