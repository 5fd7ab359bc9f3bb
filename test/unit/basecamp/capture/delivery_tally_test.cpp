#include "basecamp/capture/delivery_tally.hpp"

#include <gtest/gtest.h>

namespace tgw::basecamp {
namespace {

WriterGuid writer(std::uint8_t participant, std::uint8_t entity) {
    WriterGuid guid{};
    guid[0] = participant;
    guid[15] = entity;
    return guid;
}

ParticipantPrefix prefix(std::uint8_t participant) {
    ParticipantPrefix p{};
    p[0] = participant;
    return p;
}

DeliveryTotals totals_of(const DeliveryTally& tally, std::uint8_t participant) {
    const auto all = tally.totals();
    const auto it = all.find(prefix(participant));
    return it == all.end() ? DeliveryTotals{} : it->second;
}

TEST(DeliveryTally, CountsEverySampleAndItsBytes) {
    DeliveryTally tally;
    for (std::uint64_t seq = 1; seq <= 5; ++seq) {
        tally.add(writer(1, 1), seq, 100);
    }
    const DeliveryTotals t = totals_of(tally, 1);
    EXPECT_EQ(t.received_samples, 5u);
    EXPECT_EQ(t.received_bytes, 500u);
    EXPECT_EQ(t.lost_samples, 0u);
}

TEST(DeliveryTally, GapsInAWritersSequenceAreLosses) {
    DeliveryTally tally;
    for (std::uint64_t seq : {1u, 2u, 5u, 6u, 10u}) {
        tally.add(writer(1, 1), seq, 10);
    }
    EXPECT_EQ(totals_of(tally, 1).lost_samples, 2u + 3u);
}

TEST(DeliveryTally, WhatAWriterSentBeforeTheFirstReceivedSampleIsNotALoss) {
    DeliveryTally tally;
    tally.add(writer(1, 1), 40, 10);
    tally.add(writer(1, 1), 41, 10);
    EXPECT_EQ(totals_of(tally, 1).lost_samples, 0u);
}

TEST(DeliveryTally, ALateSampleFillsItsGapAgain) {
    DeliveryTally tally;
    tally.add(writer(1, 1), 1, 10);
    tally.add(writer(1, 1), 3, 10);
    EXPECT_EQ(totals_of(tally, 1).lost_samples, 1u);
    tally.add(writer(1, 1), 2, 10);
    EXPECT_EQ(totals_of(tally, 1).lost_samples, 0u);
    // A duplicate with no gap open takes nothing back.
    tally.add(writer(1, 1), 2, 10);
    EXPECT_EQ(totals_of(tally, 1).lost_samples, 0u);
    EXPECT_EQ(totals_of(tally, 1).received_samples, 4u);
}

TEST(DeliveryTally, WritersOfOneParticipantAddUpAndParticipantsStayApart) {
    DeliveryTally tally;
    tally.add(writer(1, 1), 1, 10);
    tally.add(writer(1, 1), 3, 10);  // one lost on writer 1
    tally.add(writer(1, 2), 7, 20);
    tally.add(writer(1, 2), 10, 20);  // two lost on writer 2
    tally.add(writer(2, 1), 1, 5);
    tally.add(writer(2, 1), 2, 5);
    const DeliveryTotals first = totals_of(tally, 1);
    EXPECT_EQ(first.received_samples, 4u);
    EXPECT_EQ(first.received_bytes, 60u);
    EXPECT_EQ(first.lost_samples, 3u);
    const DeliveryTotals second = totals_of(tally, 2);
    EXPECT_EQ(second.received_samples, 2u);
    EXPECT_EQ(second.lost_samples, 0u);
}

}  // namespace
}  // namespace tgw::basecamp
