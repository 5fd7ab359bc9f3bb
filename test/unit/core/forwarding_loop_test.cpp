#include "gateway/core/forwarding_loop.hpp"

#include <gtest/gtest.h>

#include <thread>

#include "test/fakes/recording_sink.hpp"

namespace tgw::core {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

// The loop waits in real time, so these tests use the system clock with rates chosen to finish in
// milliseconds; they wait on conditions with generous timeouts, never on fixed sleeps.
class ForwardingLoopTest : public ::testing::Test {
  protected:
    void make_sut(double rate_bps) {
        SchedulerConfig config;
        config.initial_rate_bps = rate_bps;
        sut = std::make_unique<ForwardingLoop>(config, clock, sink);
        topic = sut->add_topic({"A", seconds(5)});
        sut->start();
    }
    Sample sample(std::size_t bytes = 64) {
        Sample s;
        s.topic = topic;
        s.payload.assign(bytes, 1);
        s.source_time = clock.wall_now();
        return s;
    }

    base::SystemClock clock;
    test::RecordingSink sink;
    std::unique_ptr<ForwardingLoop> sut;
    TopicId topic = 0;
};

TEST_F(ForwardingLoopTest, ForwardsInTheSubmittingThreadWhenTheLinkIsFree) {
    make_sut(1e9);
    sut->submit(sample());
    EXPECT_EQ(sink.forwarded().size(), 1u);
}

TEST_F(ForwardingLoopTest, ReleasesQueuedSamplesAsTheLinkDrains) {
    make_sut(2'000'000);  // 1,600 wire bits each: 0.8 ms apiece
    for (int i = 0; i < 50; ++i)
        sut->submit(sample(100));
    EXPECT_TRUE(sink.wait_for_forwarded(50, milliseconds(5'000)));
}

TEST_F(ForwardingLoopTest, FollowsARateRaisedFromZero) {
    make_sut(0.0);
    sut->submit(sample());
    EXPECT_EQ(sut->queued_samples(), 1u);
    sut->set_rate(1e6);
    EXPECT_TRUE(sink.wait_for_forwarded(1, milliseconds(5'000)));
}

TEST_F(ForwardingLoopTest, StopLogsWhatIsStillQueuedAsShutdown) {
    make_sut(0.0);
    sut->submit(sample());
    sut->submit(sample());
    sut->stop();
    EXPECT_EQ(sink.dropped_count(DropReason::shutdown), 2u);
    EXPECT_TRUE(sut->total_counters().balanced());
}

TEST_F(ForwardingLoopTest, SamplesArrivingAfterStopAreLoggedNotLost) {
    make_sut(1e9);
    sut->stop();
    sut->submit(sample());
    EXPECT_EQ(sink.dropped_count(DropReason::shutdown), 1u);
}

TEST_F(ForwardingLoopTest, ConcurrentSubmittersLoseNothing) {
    make_sut(50'000'000);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t) {
        threads.emplace_back([&] {
            for (int i = 0; i < 500; ++i)
                sut->submit(sample(200));
        });
    }
    for (auto& th : threads)
        th.join();
    sut->stop();
    const TopicCounters total = sut->total_counters();
    EXPECT_EQ(total.received, 2'000u);
    EXPECT_TRUE(total.balanced());
    EXPECT_EQ(sink.forwarded().size() + sink.dropped().size(), 2'000u);
}

}  // namespace
}  // namespace tgw::core
