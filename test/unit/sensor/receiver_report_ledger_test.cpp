#include "sensor/receiver_report_ledger.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "test/fakes/fake_clock.hpp"

namespace tgw::sensor {
namespace {

constexpr std::uint64_t MAX = std::numeric_limits<std::uint64_t>::max();

ReceiverId receiver(std::uint8_t n) {
    ReceiverId id{};
    id[0] = n;
    return id;
}

class ReceiverReportLedgerTest : public ::testing::Test {
  protected:
    test::FakeClock clock;
    ReceiverReportLedger sut{clock, std::chrono::seconds(5)};
};

TEST_F(ReceiverReportLedgerTest, HasNoTotalsBeforeTheFirstReport) {
    EXPECT_FALSE(sut.latest().has_value());
}

TEST_F(ReceiverReportLedgerTest, WhatWasForwardedAndNeitherReceivedNorLostIsInFlight) {
    ASSERT_TRUE(sut.take(receiver(1), {100, 5'000, 0}, 100));  // the first report: nothing pending
    clock.advance(std::chrono::seconds(1));
    ASSERT_TRUE(sut.take(receiver(1), {150, 7'500, 2}, 160));
    const auto totals = sut.latest();
    ASSERT_TRUE(totals.has_value());
    EXPECT_EQ(totals->received_samples, 150u);
    EXPECT_EQ(totals->received_bytes, 7'500u);
    EXPECT_EQ(totals->lost_samples, 2u);
    EXPECT_EQ(totals->in_flight_samples, 8u);
    EXPECT_EQ(totals->reports, 2u);
}

TEST_F(ReceiverReportLedgerTest, WhatWentOutBeforeTheReceiverMatchedIsNeverInFlight) {
    ASSERT_TRUE(sut.take(receiver(1), {0, 0, 0}, 40));  // 40 written to no one
    ASSERT_TRUE(sut.take(receiver(1), {10, 500, 0}, 55));
    EXPECT_EQ(sut.latest()->in_flight_samples, 5u);
}

TEST_F(ReceiverReportLedgerTest, FollowsTheFirstReceiverAndIgnoresOthers) {
    ASSERT_TRUE(sut.take(receiver(1), {10, 500, 0}, 10));
    EXPECT_FALSE(sut.take(receiver(2), {99, 9'900, 9}, 10));
    EXPECT_EQ(sut.latest()->received_samples, 10u);
}

TEST_F(ReceiverReportLedgerTest, ASilentReceiverIsGivenUpAndTheNextOneFollowed) {
    ASSERT_TRUE(sut.take(receiver(1), {10, 500, 0}, 10));
    clock.advance(std::chrono::seconds(4));
    EXPECT_TRUE(sut.latest().has_value());
    clock.advance(std::chrono::seconds(2));
    EXPECT_FALSE(sut.latest().has_value()) << "a report 6 s old says nothing of the link now";

    // The base camp restarted: a new participant whose counts start again from zero.
    ASSERT_TRUE(sut.take(receiver(2), {3, 150, 0}, 40));
    ASSERT_TRUE(sut.take(receiver(2), {8, 400, 0}, 45));
    const auto totals = sut.latest();
    ASSERT_TRUE(totals.has_value());
    EXPECT_EQ(totals->received_samples, 8u);
    EXPECT_EQ(totals->in_flight_samples, 0u) << "what the old receiver saw is not pending at the new one";
    EXPECT_EQ(totals->reports, 2u);
    EXPECT_FALSE(sut.take(receiver(1), {11, 550, 0}, 45)) << "the old one, back, is now the other";
}

TEST_F(ReceiverReportLedgerTest, CountsNearTheLimitSaturateInsteadOfWrapping) {
    ASSERT_TRUE(sut.take(receiver(1), {5, 250, 0}, 10));
    // received + lost wraps to 1 in 64 bits, which would leave 19 of 20 "in flight".
    ASSERT_TRUE(sut.take(receiver(1), {MAX, 0, 2}, 20));
    EXPECT_EQ(sut.latest()->in_flight_samples, 0u);
}

TEST(ReceiverCountsTest, ConvertsTotalsToWireBytes) {
    ReceiverReportTotals totals;
    totals.received_samples = 10;
    totals.received_bytes = 1'000;
    totals.lost_samples = 2;
    totals.in_flight_samples = 3;
    const ReceiverCounts counts = receiver_counts(totals, 138 + 36, 250);
    EXPECT_EQ(counts.received_wire_bytes, 1'000u + 10u * 174u);
    EXPECT_EQ(counts.lost_samples, 2u);
    EXPECT_EQ(counts.in_flight_bytes, 750u);
}

TEST(ReceiverCountsTest, AbsurdCountsSaturate) {
    ReceiverReportTotals totals;
    totals.received_samples = MAX / 2;
    totals.received_bytes = MAX - 5;
    totals.in_flight_samples = MAX / 3;
    const ReceiverCounts counts = receiver_counts(totals, 174, 1'000);
    EXPECT_EQ(counts.received_wire_bytes, MAX);
    EXPECT_EQ(counts.in_flight_bytes, MAX);
}

}  // namespace
}  // namespace tgw::sensor
