#include "core/backfill_planner.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace tgw::core {
namespace {

using namespace std::chrono_literals;

const base::SteadyTime T0{1000s};
const base::WallTime W0{1'700'000'000s};

BackfillRow row(std::int64_t id, base::Duration ttl, base::Duration born_after_w0, std::size_t bytes = 100) {
    return BackfillRow{id, ttl, W0 + born_after_w0, bytes};
}

/// The ids take() hands out at `now`, in order, until it hands out none.
std::vector<std::int64_t> take_all(BackfillPlanner& planner, base::SteadyTime now) {
    std::vector<std::int64_t> ids;
    while (const std::optional<BackfillRow> next = planner.take(now))
        ids.push_back(next->id);
    return ids;
}

TEST(BackfillPlannerTest, ShortestTtlFirstThenOldestFirst) {
    BackfillPlanner planner({});
    planner.add(row(1, 20s, 0s));  // D, oldest of all
    planner.add(row(2, 1s, 3s));   // A
    planner.add(row(3, 5s, 1s));   // C
    planner.add(row(4, 1s, 2s));   // A, older than 2
    planner.add(row(5, 5s, 1s));   // C born with 3: the log's order breaks the tie
    EXPECT_EQ(take_all(planner, T0), (std::vector<std::int64_t>{4, 2, 3, 5, 1}));
}

TEST(BackfillPlannerTest, ARowKnownAlreadyIsNotAddedTwice) {
    BackfillPlanner planner({});
    planner.add(row(1, 1s, 0s));
    planner.add(row(1, 1s, 0s));
    EXPECT_EQ(planner.backlog().rows, 1u);
    EXPECT_EQ(take_all(planner, T0), (std::vector<std::int64_t>{1}));
}

TEST(BackfillPlannerTest, ARowTakenIsNotTakenAgainUntilItIsKnownNotToHaveLeft) {
    BackfillPlanner planner({});
    planner.add(row(1, 1s, 0s));
    planner.add(row(2, 2s, 0s));
    ASSERT_EQ(planner.take(T0)->id, 1);
    EXPECT_EQ(planner.take(T0)->id, 2) << "1 is on its way";
    EXPECT_FALSE(planner.take(T0));
    planner.not_sent(1);  // the schedule dropped it, or its write failed
    EXPECT_EQ(planner.take(T0)->id, 1) << "at once: it never reached the link";
}

TEST(BackfillPlannerTest, ARowSentGoesAgainOnlyWhenNoAcknowledgementCameWithinTheResendTime) {
    BackfillPlanner planner({5s, 0.0});
    planner.add(row(1, 1s, 0s));
    ASSERT_EQ(planner.take(T0)->id, 1);
    planner.sent(1, 800, T0);
    EXPECT_FALSE(planner.take(T0 + 4999ms)) << "its acknowledgement may still come";
    ASSERT_EQ(planner.next_wakeup(T0), T0 + 5s);
    EXPECT_EQ(planner.take(T0 + 5s)->id, 1) << "lost on the way, or its acknowledgement was";
    planner.sent(1, 800, T0 + 5s);
    planner.acknowledged(1);
    EXPECT_FALSE(planner.take(T0 + 60s)) << "the camp has it";
    EXPECT_FALSE(planner.next_wakeup(T0 + 60s));
    EXPECT_EQ(planner.backlog().rows, 0u);
}

TEST(BackfillPlannerTest, AnAcknowledgementOfARowNotYetSentFreesIt) {
    // A gateway that restarted sends again what the camp stored before: an acknowledgement may come for any row.
    BackfillPlanner planner({});
    planner.add(row(1, 1s, 0s));
    planner.add(row(2, 1s, 1s));
    planner.acknowledged(1);
    planner.acknowledged(99);  // never known here: nothing happens
    EXPECT_EQ(take_all(planner, T0), (std::vector<std::int64_t>{2}));
}

TEST(BackfillPlannerTest, ARangeOfAcknowledgementsFreesTheKnownRowsInIt) {
    BackfillPlanner planner({});
    for (std::int64_t id : {3, 5, 6, 9, 12})
        planner.add(row(id, 1s, std::chrono::seconds(id)));
    ASSERT_EQ(planner.take(T0)->id, 3);
    planner.sent(3, 800, T0);
    EXPECT_EQ(planner.acknowledged(1, 9), 4u) << "3 (sent), 5, 6 and 9; 1, 2, 4, 7 and 8 were never known";
    EXPECT_EQ(planner.acknowledged(0, std::numeric_limits<std::int64_t>::max()), 1u) << "12: a range of any size";
    EXPECT_EQ(planner.backlog().rows, 0u);
    EXPECT_FALSE(planner.take(T0 + 60s));
}

TEST(BackfillPlannerTest, AnAcknowledgedRowThatTheSenderStillHoldsIsNotMadeReadyAgain) {
    BackfillPlanner planner({});
    planner.add(row(1, 1s, 0s));
    ASSERT_EQ(planner.take(T0)->id, 1);
    planner.acknowledged(1);  // from an earlier send, before this one left
    planner.not_sent(1);
    planner.sent(1, 800, T0);
    EXPECT_FALSE(planner.take(T0 + 60s));
    EXPECT_EQ(planner.backlog().rows, 0u);
}

TEST(BackfillPlannerTest, TheCapSpacesRowsByTheBitsTheLastOneTook) {
    BackfillPlanner planner({5s, 1000.0});  // 1,000 bit/s
    for (std::int64_t id = 1; id <= 3; ++id)
        planner.add(row(id, 1s, std::chrono::seconds(id)));
    ASSERT_EQ(planner.take(T0)->id, 1);
    planner.sent(1, 500, T0);  // half a second at the cap
    EXPECT_FALSE(planner.take(T0 + 499ms));
    EXPECT_EQ(planner.next_wakeup(T0), T0 + 500ms);
    ASSERT_EQ(planner.take(T0 + 500ms)->id, 2);
    planner.sent(2, 2000, T0 + 600ms);  // left later than the cap allowed: counted from when it left
    EXPECT_FALSE(planner.take(T0 + 2599ms));
    EXPECT_EQ(planner.take(T0 + 2600ms)->id, 3);
}

TEST(BackfillPlannerTest, WithoutACapOnlyTheScheduleSpacesThem) {
    BackfillPlanner planner({5s, 0.0});
    planner.add(row(1, 1s, 0s));
    planner.add(row(2, 1s, 1s));
    ASSERT_EQ(planner.take(T0)->id, 1);
    planner.sent(1, 1'000'000, T0);
    EXPECT_EQ(planner.take(T0)->id, 2);
}

TEST(BackfillPlannerTest, TheBacklogCountsEveryRowNotAcknowledged) {
    BackfillPlanner planner({});
    EXPECT_EQ(planner.backlog().rows, 0u);
    EXPECT_FALSE(planner.backlog().oldest);
    planner.add(row(1, 20s, 5s, 1000));
    planner.add(row(2, 1s, 2s, 40));
    planner.add(row(3, 2s, 9s, 60));
    ASSERT_EQ(planner.take(T0)->id, 2);
    planner.sent(2, 800, T0);  // sent, not acknowledged: still the robot's only copy
    BackfillPlanner::Backlog backlog = planner.backlog();
    EXPECT_EQ(backlog.rows, 3u);
    EXPECT_EQ(backlog.bytes, 1100u);
    EXPECT_EQ(backlog.oldest, W0 + 2s);
    planner.acknowledged(2);
    backlog = planner.backlog();
    EXPECT_EQ(backlog.rows, 2u);
    EXPECT_EQ(backlog.bytes, 1060u);
    EXPECT_EQ(backlog.oldest, W0 + 5s);
}

TEST(BackfillPlannerTest, ARowForgottenIsGoneWhereverItWas) {
    // The log pruned it before the camp had it (an unacknowledged row, the cap reached).
    BackfillPlanner planner({});
    planner.add(row(1, 1s, 0s));
    planner.add(row(2, 1s, 1s));
    planner.add(row(3, 1s, 2s));
    ASSERT_EQ(planner.take(T0)->id, 1);
    planner.sent(1, 800, T0);
    planner.forget(1);
    planner.forget(2);
    EXPECT_EQ(take_all(planner, T0 + 60s), (std::vector<std::int64_t>{3}));
    EXPECT_EQ(planner.backlog().rows, 1u);
}

TEST(BackfillPlannerTest, NoWakeupWhileEveryRowIsReadyOrOnItsWay) {
    BackfillPlanner planner({});
    EXPECT_FALSE(planner.next_wakeup(T0)) << "nothing at all";
    planner.add(row(1, 1s, 0s));
    EXPECT_EQ(planner.next_wakeup(T0), T0) << "ready now";
    ASSERT_TRUE(planner.take(T0));
    EXPECT_FALSE(planner.next_wakeup(T0)) << "taken: its fate is told by sent() or not_sent()";
}

}  // namespace
}  // namespace tgw::core
