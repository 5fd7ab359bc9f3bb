#include "core/link_budget.hpp"

#include <gtest/gtest.h>

namespace tgw::core {
namespace {

using std::chrono::milliseconds;

class LinkBudgetTest : public ::testing::Test {
  protected:
    base::SteadyTime t0{std::chrono::seconds(100)};
    LinkBudget sut{10'000.0, milliseconds(0)};
};

TEST_F(LinkBudgetTest, TransmitTimeIsBitsOverRate) {
    EXPECT_EQ(sut.transmit_time(1'000), milliseconds(100));
}

TEST_F(LinkBudgetTest, LinkIsBusyUntilChargedBitsHaveDrained) {
    EXPECT_TRUE(sut.can_send(t0));
    EXPECT_EQ(sut.charge(t0, 1'000), t0 + milliseconds(100));
    EXPECT_FALSE(sut.can_send(t0 + milliseconds(99)));
    EXPECT_TRUE(sut.can_send(t0 + milliseconds(100)));
}

TEST_F(LinkBudgetTest, ChargesQueueBehindEachOther) {
    sut.charge(t0, 1'000);
    EXPECT_EQ(sut.charge(t0 + milliseconds(50), 1'000), t0 + milliseconds(200));
}

TEST_F(LinkBudgetTest, IdleTimeIsNotBanked) {
    sut.charge(t0, 1'000);
    EXPECT_EQ(sut.charge(t0 + milliseconds(500), 1'000), t0 + milliseconds(600));
}

TEST_F(LinkBudgetTest, LeadAdmitsTheNextSampleJustBeforeTheLinkDrains) {
    LinkBudget with_lead(10'000.0, milliseconds(5));
    with_lead.charge(t0, 1'000);
    EXPECT_FALSE(with_lead.can_send(t0 + milliseconds(94)));
    EXPECT_TRUE(with_lead.can_send(t0 + milliseconds(95)));
}

TEST_F(LinkBudgetTest, ZeroRateAdmitsNothing) {
    sut.set_rate(0.0);
    EXPECT_FALSE(sut.can_send(t0));
    EXPECT_EQ(sut.transmit_time(1), base::Duration::max());
}

TEST_F(LinkBudgetTest, NewRateAppliesToTheNextCharge) {
    sut.charge(t0, 1'000);
    sut.set_rate(20'000.0);
    EXPECT_EQ(sut.charge(t0, 1'000), t0 + milliseconds(150));
}

}  // namespace
}  // namespace tgw::core
