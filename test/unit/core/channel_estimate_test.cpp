#include "core/channel_estimate.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "base/config_error.hpp"
#include "test/fakes/fake_clock.hpp"

namespace tgw::core {
namespace {

using namespace std::chrono_literals;

constexpr double BOUND = 60'000;

/// A base camp's view of a channel: each second, what arrived from two robots and how long it took.
class ChannelEstimateTest : public ::testing::Test {
  protected:
    explicit ChannelEstimateTest(const ChannelEstimateConfig& config = without_slow_start())
        : estimate_{BOUND, config, clock_} {}

    /// One second: `bps` delivered in 250-byte samples, half from each robot, each after `delay` on the way
    /// (rover2's clock 7 s ahead of the camp's), `lost` samples more lost; then the estimate's update with
    /// `granted` handed out.
    double second(double bps, base::Duration delay, double granted, std::uint64_t lost = 0) {
        const auto samples = static_cast<int>(std::lround(bps / 8 / SAMPLE_BYTES));
        for (int i = 0; i < samples; ++i) {
            const bool rover1 = i % 2 == 0;
            estimate_.arrived(rover1 ? "rover1" : "rover2", rover1 ? delay : delay - 7s, SAMPLE_BYTES);
        }
        clock_.advance(1s);
        delivered_ += static_cast<std::uint64_t>(samples) * SAMPLE_BYTES;
        lost_ += lost;
        return estimate_.update(delivered_, lost_, granted);
    }

    /// A channel of 30,000 bit/s carrying all it is given, delays at their least; the robots ask less than their
    /// grants, so nothing says the channel is smaller than its bound.
    void settle() {
        for (int i = 0; i < 3; ++i) {
            second(30'000, 40ms, 54'000);
        }
        ASSERT_EQ(estimate_.verdict(), ChannelVerdict::clear);
    }

    /// The AIMD from the bound: the slow start has tests of its own (ChannelSlowStartTest).
    static ChannelEstimateConfig without_slow_start() {
        ChannelEstimateConfig config;
        config.start_fraction = 1.0;
        return config;
    }

    static constexpr std::size_t SAMPLE_BYTES = 250;
    test::FakeClock clock_;
    ChannelEstimate estimate_;
    std::uint64_t delivered_ = 0;
    std::uint64_t lost_ = 0;
};

TEST_F(ChannelEstimateTest, AChannelThatCarriesWhatItIsGivenStaysAtTheBound) {
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::unknown);
    for (int i = 0; i < 20; ++i) {
        EXPECT_DOUBLE_EQ(second(50'000, 40ms, 54'000), BOUND) << "second " << i;
    }
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::clear);
    EXPECT_NEAR(*estimate_.delivered_bps(), 50'000, 500);
    EXPECT_EQ(*estimate_.queueing(), 0ms) << "the offsets of both clocks cancel";
}

TEST_F(ChannelEstimateTest, AGrowingQueueCutsToAFractionOfWhatTheChannelDelivered) {
    settle();
    // The robots ask for their grants: 54,000 bit/s into the channel's 30,000 fill the router's queue.
    second(30'000, 340ms, 54'000);
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::queueing);
    EXPECT_NEAR(estimate_.channel_bps(), 0.9 * 30'000, 500);
    EXPECT_NEAR(estimate_.queueing()->count(), std::chrono::nanoseconds(300ms).count(), 1e6);
}

// A robot away for 2 s, the others held to their grants: the channel carried less than it could. When the robot
// returns, a queue forms: its second shows what the channel carries, the seconds before it did not.
TEST_F(ChannelEstimateTest, AQueueAfterAQuietSpellCutsToWhatTheChannelCarriedInIt) {
    settle();
    second(12'000, 40ms, 54'000);
    second(12'000, 40ms, 54'000);
    second(30'000, 340ms, 54'000);
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::queueing);
    EXPECT_NEAR(estimate_.channel_bps(), 0.9 * 30'000, 500) << "not 0.9 of the window's 18,000";
}

// A gateway restarted into a running fleet (rover3) announces itself in a burst of discovery that the camp's
// relay does not see (a discovery server takes it): a queue while the channel looks half used. Cut to what was
// delivered, the others' grants halved for a burst that drains by itself.
TEST_F(ChannelEstimateTest, AQueueWhileASenderJoinsARunningFleetCutsToTheMostItDeliveredLately) {
    for (int i = 0; i < 12; ++i) {
        second(i >= 3 && i < 8 ? 50'000 : 30'000, 40ms, 54'000);  // rover1 and rover2, known longer than joining
    }
    estimate_.arrived("rover3", 2s + 340ms, SAMPLE_BYTES);
    second(20'000, 340ms, 54'000);
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::queueing);
    EXPECT_NEAR(estimate_.channel_bps(), 50'000, 500) << "not 0.9 of the 20,000 the camp saw";

    // A cut in every decrease_interval the queue stands: by a twentieth while what was delivered lately is more.
    clock_.advance(1s);
    second(20'000, 340ms, 54'000);
    EXPECT_NEAR(estimate_.channel_bps(), 0.95 * 50'000, 500);

    // Once it is known as long as the others, a queue cuts to what the channel delivered again.
    clock_.advance(without_slow_start().joining);
    estimate_.update(delivered_, lost_, 54'000);
    estimate_.arrived("rover3", 2s + 340ms, SAMPLE_BYTES);
    second(20'000, 340ms, 54'000);
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::queueing);
    EXPECT_NEAR(estimate_.channel_bps(), 0.9 * 20'000, 500);
}

// With a discovery server, the relay hears of rover3's new participant seconds before its first sample, and its
// discovery queues the channel meanwhile.
TEST_F(ChannelEstimateTest, AParticipantThatJoinedCountsAsJoiningBeforeItsFirstSample) {
    for (int i = 0; i < 12; ++i) {
        second(30'000, 40ms, 54'000);
    }
    estimate_.participant_joined();
    second(20'000, 340ms, 54'000);
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::queueing);
    EXPECT_NEAR(estimate_.channel_bps(), 30'000, 500) << "the most delivered lately";
}

TEST_F(ChannelEstimateTest, AShortQueueEasesTheEstimateDownWithoutACut) {
    settle();
    second(30'000, 340ms, 54'000);
    double before = estimate_.channel_bps();
    for (int i = 0; i < 5; ++i) {
        // Between full and a cut (each sample's own time on the wire aside): down, slower than the growth rate.
        const double now = second(0.8 * before, 215ms, 0.9 * before);
        EXPECT_LT(now, before) << "second " << i;
        EXPECT_GT(now, before - 0.02 * BOUND) << "second " << i;
        EXPECT_EQ(estimate_.verdict(), ChannelVerdict::full);
        before = estimate_.channel_bps();
    }
}

TEST_F(ChannelEstimateTest, GrowsTheSlowerTheNearerTheQueueIsToFull) {
    settle();
    second(30'000, 340ms, 54'000);
    const double cut = estimate_.channel_bps();
    const double grown = second(0.9 * cut, 90ms, 0.9 * cut);  // 50 ms above the least, less its time on the wire
    EXPECT_GT(grown, cut);
    EXPECT_LT(grown, cut + 0.02 * BOUND) << "slower than on a clear channel";
}

TEST_F(ChannelEstimateTest, AShrinkingQueueIsLeftToDrain) {
    settle();
    second(30'000, 640ms, 54'000);
    const double cut = estimate_.channel_bps();
    clock_.advance(5s);  // past the decrease interval: only the draining holds the next cut back
    EXPECT_DOUBLE_EQ(second(30'000, 540ms, 24'000), cut);
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::draining);
    EXPECT_DOUBLE_EQ(second(30'000, 340ms, 24'000), cut);
    second(30'000, 40ms, 24'000);
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::clear);
}

TEST_F(ChannelEstimateTest, OneCutPerIntervalWhileTheLastCanShowNothingYet) {
    settle();
    second(30'000, 340ms, 54'000);
    const double cut = estimate_.channel_bps();
    EXPECT_DOUBLE_EQ(second(20'000, 640ms, 24'000), cut) << "a second after the cut";
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::queueing);
    EXPECT_NEAR(second(20'000, 940ms, 24'000), 0.9 * (30'000 + 20'000 + 20'000) / 3, 500)
        << "two seconds after it, at what the last three delivered";
}

TEST_F(ChannelEstimateTest, LostSamplesCutWithoutAQueue) {
    settle();
    EXPECT_NEAR(second(40'000, 40ms, 54'000, 3), 0.9 * (30'000 + 30'000 + 40'000) / 3, 500);
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::losing);
}

TEST_F(ChannelEstimateTest, GrowsBackWhileTheRobotsUseItAndNothingQueues) {
    settle();
    second(30'000, 340ms, 54'000);
    const double cut = estimate_.channel_bps();
    // The robots use all they are granted (90 % of the estimate): a fiftieth of the bound a second.
    EXPECT_NEAR(second(0.9 * cut, 40ms, 0.9 * cut), cut + 0.02 * BOUND, 1);
    for (int i = 0; i < 60; ++i) {
        const double now = estimate_.channel_bps();
        second(0.9 * now, 40ms, 0.9 * now);
    }
    EXPECT_DOUBLE_EQ(estimate_.channel_bps(), BOUND) << "never above the bound";
}

TEST_F(ChannelEstimateTest, AnIdleChannelProvesNothing) {
    settle();
    second(30'000, 340ms, 54'000);
    for (int i = 0; i < 3; ++i) {
        second(5'000, 40ms, 24'000);  // the busy seconds leave the delivered window
    }
    const double held = estimate_.channel_bps();
    for (int i = 0; i < 10; ++i) {
        EXPECT_DOUBLE_EQ(second(5'000, 40ms, 24'000), held) << "second " << i;
    }
}

TEST_F(ChannelEstimateTest, BytesWithoutDelaysProveNothing) {
    settle();
    second(30'000, 340ms, 54'000);
    const double cut = estimate_.channel_bps();
    for (int i = 0; i < 5; ++i) {
        clock_.advance(1s);
        delivered_ += 3'000;  // 24,000 bit/s of datagrams no sender stamped
        EXPECT_DOUBLE_EQ(estimate_.update(delivered_, lost_, 24'000), cut) << "second " << i;
    }
}

TEST_F(ChannelEstimateTest, NeverBelowItsLeastFractionOfTheBound) {
    settle();
    for (int i = 0; i < 20; ++i) {
        second(0, 40ms, 54'000, 1);
    }
    EXPECT_DOUBLE_EQ(estimate_.channel_bps(), 0.1 * BOUND);
}

// The grants hand out the whole estimate, used or not: what proves the channel is what it carried.
TEST_F(ChannelEstimateTest, AnEstimateTheRobotsUseOnlyPartOfDoesNotGrow) {
    settle();
    second(30'000, 340ms, 54'000);
    const double cut = estimate_.channel_bps();
    for (int i = 0; i < 3; ++i) {
        second(0.7 * cut, 40ms, 0.9 * cut);  // the busier seconds leave the delivered window
    }
    const double used = estimate_.channel_bps();
    for (int i = 0; i < 10; ++i) {
        // 70 % of it, and of the grants 78 %: growth, judged against the grants.
        EXPECT_DOUBLE_EQ(second(0.7 * used, 40ms, 0.9 * used), used) << "second " << i;
    }
}

TEST_F(ChannelEstimateTest, ALargeSampleTakesLongerOnTheWireWithoutQueueing) {
    settle();
    // 3,000 bytes at the bound take 400 ms to cross; each alone in its second.
    for (int i = 0; i < 3; ++i) {
        estimate_.arrived("rover1", 40ms + 400ms, 3'000);
        clock_.advance(1s);
        delivered_ += 3'000;
        EXPECT_DOUBLE_EQ(estimate_.update(delivered_, lost_, 54'000), BOUND);
        EXPECT_LT(*estimate_.queueing(), 50ms);
    }
}

TEST_F(ChannelEstimateTest, ASendersQuickestDelayIsForgottenAfterTheBaselineWindow) {
    // rover1's clock jumps 2 s back (a time server corrected it): every sample now seems 2 s slower.
    const ChannelEstimateConfig config;
    ChannelEstimate estimate(BOUND, config, clock_);
    estimate.arrived("rover1", 40ms, SAMPLE_BYTES);
    for (int i = 0; i < 7; ++i) {
        clock_.advance(config.baseline_window / 5);
        estimate.arrived("rover1", 2040ms, SAMPLE_BYTES);
    }
    clock_.advance(1s);
    estimate.update(0, 0, 0);
    clock_.advance(1s);
    estimate.arrived("rover1", 2040ms, SAMPLE_BYTES);
    estimate.update(SAMPLE_BYTES, 0, 0);
    EXPECT_LT(*estimate.queueing(), 10ms) << "its new delay is its least now";
}

TEST_F(ChannelEstimateTest, AGatewayThatJoinsAStandingQueueDoesNotHideIt) {
    const ChannelEstimateConfig config = without_slow_start();
    for (int i = 0; i < 12; ++i) {
        second(30'000, 40ms, 54'000);  // rover1 and rover2, known for longer than config.joining
    }
    // A restarted gateway's first samples come through the router's queue of 300 ms, as the others' do: its
    // quickest delay is a queued one (its clock 3 s behind the camp's).
    const auto queued_second = [&](bool others) {
        for (int i = 0; i < 10; ++i) {
            estimate_.arrived("rover3", 3s + 340ms, SAMPLE_BYTES);
        }
        if (others) {
            for (int i = 0; i < 10; ++i) {
                estimate_.arrived("rover1", 340ms, SAMPLE_BYTES);
            }
        }
        clock_.advance(1s);
        delivered_ += (others ? 20 : 10) * SAMPLE_BYTES;
        return estimate_.update(delivered_, lost_, 54'000);
    };
    queued_second(true);
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::queueing);
    EXPECT_NEAR(estimate_.queueing()->count(), std::chrono::nanoseconds(300ms).count(), 1e6);
    EXPECT_LT(estimate_.channel_bps(), BOUND);

    // Past its joining window, its delays count, its quickest taken without the queue it joined: alone, it tells
    // the queue that still stands.
    clock_.advance(config.joining);
    estimate_.update(delivered_, lost_, 54'000);
    queued_second(false);
    ASSERT_TRUE(estimate_.queueing());
    EXPECT_NEAR(estimate_.queueing()->count(), std::chrono::nanoseconds(300ms).count(), 1e6);
}

TEST_F(ChannelEstimateTest, CountersThatGoBackStartAfresh) {
    settle();
    clock_.advance(1s);
    EXPECT_DOUBLE_EQ(estimate_.update(0, 0, 54'000), BOUND) << "the relay restarted its tally";
    clock_.advance(1s);
    EXPECT_DOUBLE_EQ(estimate_.update(6'000, 0, 54'000), BOUND);
    EXPECT_NEAR(*estimate_.delivered_bps(), 48'000, 1);
}

/// A fleet's start: the estimate from a quarter of its bound, the robots using what they are granted.
class ChannelSlowStartTest : public ChannelEstimateTest {
  protected:
    ChannelSlowStartTest() : ChannelEstimateTest(ChannelEstimateConfig{}) {}

    /// A second of the channel carrying 95 % of the estimate, granted 90 %, with `delay` on the way.
    double used_second(base::Duration delay = 40ms) {
        const double now = estimate_.channel_bps();
        return second(0.95 * now, delay, 0.9 * now);
    }
};

TEST_F(ChannelSlowStartTest, StartsAtAQuarterOfTheBoundAndGrowsByATenthOfItselfASecondWhileUsed) {
    EXPECT_DOUBLE_EQ(estimate_.channel_bps(), 0.25 * BOUND);
    used_second();  // the first update only starts the count
    EXPECT_NEAR(used_second(), 0.25 * BOUND * 1.1, 1);
    EXPECT_NEAR(used_second(), 0.25 * BOUND * 1.1 * 1.1, 1);
    for (int i = 0; i < 30; ++i) {
        used_second();
    }
    EXPECT_DOUBLE_EQ(estimate_.channel_bps(), BOUND) << "never above the bound";
}

// At the bound's wire time, not the estimate's: a 3,000-byte bundle takes 0.4 s at the bound, 1.6 s at a quarter.
TEST_F(ChannelSlowStartTest, ALargeBundleIsNotTheQuickestEverBeforeTheFirstQueue) {
    estimate_.arrived("rover1", 40ms, SAMPLE_BYTES);
    estimate_.arrived("rover1", 440ms, 3'000);  // 0.4 s on the wire at the bound, no queue
    clock_.advance(1s);
    estimate_.update(3'250, 0, 0);
    clock_.advance(1s);
    estimate_.arrived("rover1", 40ms, SAMPLE_BYTES);
    estimate_.update(3'500, 0, 0);
    EXPECT_LT(*estimate_.queueing(), 10ms);
}

TEST_F(ChannelSlowStartTest, AnIdleChannelDoesNotGrowIt) {
    for (int i = 0; i < 10; ++i) {
        EXPECT_DOUBLE_EQ(second(2'000, 40ms, 0.25 * BOUND), 0.25 * BOUND) << "second " << i;
    }
}

TEST_F(ChannelSlowStartTest, TheFirstShortQueueEndsIt) {
    used_second(40ms);
    used_second(40ms);
    used_second(40ms);
    const double before = estimate_.channel_bps();
    used_second(190ms);  // 150 ms above the least: a short queue stands
    EXPECT_EQ(estimate_.verdict(), ChannelVerdict::full);
    const double eased = estimate_.channel_bps();
    EXPECT_LT(eased, *estimate_.delivered_bps()) << "down to what the channel carried, and eased from there";
    EXPECT_LT(*estimate_.delivered_bps(), before);
    // Clear again: it grows by a fiftieth of the bound a second, no longer by a tenth of itself.
    EXPECT_NEAR(used_second(40ms), eased + 0.02 * BOUND, 1);
}

TEST(ChannelEstimateConfigTest, NamesTheFieldThatIsWrong) {
    ChannelEstimateConfig config;
    EXPECT_EQ(config.validate(), "");
    config.decrease_factor = 1.0;
    EXPECT_NE(config.validate().find("decrease_factor"), std::string::npos);
    config = {};
    config.min_fraction = 0;
    EXPECT_NE(config.validate().find("min_fraction"), std::string::npos);
    config = {};
    config.hold_queueing = 1s;
    EXPECT_NE(config.validate().find("hold_queueing"), std::string::npos);
    config = {};
    config.start_fraction = 0;
    EXPECT_NE(config.validate().find("start_fraction"), std::string::npos);
    config = {};
    config.start_growth_per_s = -1;
    EXPECT_NE(config.validate().find("start_growth_per_s"), std::string::npos);
    config = {};
    config.joining = -1s;
    EXPECT_NE(config.validate().find("joining"), std::string::npos);
    config = {};
    config.interval = 0s;
    EXPECT_NE(config.validate().find("interval"), std::string::npos);
    test::FakeClock clock;
    EXPECT_THROW(ChannelEstimate(0, {}, clock), base::ConfigError);
    EXPECT_THROW(ChannelEstimate(BOUND, config, clock), base::ConfigError);
}

}  // namespace
}  // namespace tgw::core
