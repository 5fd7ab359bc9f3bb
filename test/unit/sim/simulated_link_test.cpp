#include "gateway/sim/simulated_link.hpp"

#include <gtest/gtest.h>

namespace tgw::sim {
namespace {

using std::chrono::milliseconds;

class SimulatedLinkTest : public ::testing::Test {
  protected:
    core::SteadyTime t0{std::chrono::hours(1)};
    SimulatedLink sut{RateProfile::constant(10'000), t0, milliseconds(250)};
};

TEST_F(SimulatedLinkTest, PacketsQueueBehindEachOther) {
    EXPECT_EQ(*sut.send(t0, 1'000), t0 + milliseconds(100));
    EXPECT_EQ(*sut.send(t0, 1'000), t0 + milliseconds(200));
}

TEST_F(SimulatedLinkTest, DropsAPacketThatWouldWaitLongerThanTheQueueLimit) {
    sut.send(t0, 3'000);  // holds the link for 300 ms
    EXPECT_FALSE(sut.send(t0, 1'000));
    EXPECT_EQ(sut.dropped_bits(), 1'000u);
    EXPECT_EQ(sut.sent_bits(), 3'000u);
}

TEST_F(SimulatedLinkTest, AnIdleLinkStartsAtOnce) {
    sut.send(t0, 1'000);
    EXPECT_EQ(*sut.send(t0 + milliseconds(500), 1'000), t0 + milliseconds(600));
}

}  // namespace
}  // namespace tgw::sim
