#include "core/sent_rate.hpp"

#include <gtest/gtest.h>

#include "test/fakes/fake_clock.hpp"

namespace tgw::core {
namespace {

using namespace std::chrono_literals;

// Commands at 10 Hz of 154 bytes on the wire each (a 48-byte command in its own RTPS datagram).
constexpr std::uint64_t COMMAND_BYTES = 154;

class SentRateTest : public ::testing::Test {
  protected:
    // Polled every 100 ms, as the relay polls its grantor; `commands` more sent at each poll where given.
    void run(base::Duration how_long, int commands_per_poll) {
        for (base::Duration t{}; t < how_long; t += 100ms) {
            clock_.advance(100ms);
            total_ += static_cast<std::uint64_t>(commands_per_poll) * COMMAND_BYTES;
            rate_.update(clock_.now(), total_);
        }
    }

    test::FakeClock clock_;
    SentRate rate_;
    std::uint64_t total_ = 0;
};

TEST_F(SentRateTest, NothingSentIsNoRate) {
    EXPECT_EQ(rate_.bps(clock_.now()), 0.0);
    run(3s, 0);
    EXPECT_EQ(rate_.bps(clock_.now()), 0.0);
}

TEST_F(SentRateTest, SteadyCommandsAreTheirRate) {
    run(5s, 1);
    EXPECT_NEAR(rate_.bps(clock_.now()), 10 * COMMAND_BYTES * 8, 1.0);
}

// The grant must make room as soon as the commands begin: a robot whose share leaves them no room starves, and its
// statuses, which would ask for more, starve with it.
TEST_F(SentRateTest, CommandsThatHaveJustBegunCountAtTheirRate) {
    run(10s, 0);
    run(1s, 1);
    EXPECT_NEAR(rate_.bps(clock_.now()), 10 * COMMAND_BYTES * 8, 10 * COMMAND_BYTES * 8 * 0.15);
    // Their first two are not a rate: counted over MIN_ACTIVE.
    SentRate fresh;
    fresh.update(clock_.now(), 0);
    clock_.advance(100ms);
    fresh.update(clock_.now(), 2 * COMMAND_BYTES);
    EXPECT_DOUBLE_EQ(fresh.bps(clock_.now()), 2.0 * COMMAND_BYTES * 8 / 0.5);
}

TEST_F(SentRateTest, CommandsThatStoppedCountNoMoreAfterAWindow) {
    run(5s, 1);
    run(1s, 0);
    const double fading = rate_.bps(clock_.now());
    EXPECT_GT(fading, 0.0);
    EXPECT_LT(fading, 10 * COMMAND_BYTES * 8);
    run(1s, 0);
    EXPECT_EQ(rate_.bps(clock_.now()), 0.0);
}

}  // namespace
}  // namespace tgw::core
