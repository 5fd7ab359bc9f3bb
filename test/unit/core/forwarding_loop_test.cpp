#include "core/forwarding_loop.hpp"

#include <gtest/gtest.h>

#include <future>
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
    void make_sut(double rate_bps, bool bundles = false) {
        SchedulerConfig config;
        config.initial_rate_bps = rate_bps;
        if (bundles) {
            config.bundles = BundleLimits{};
        }
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
    /// After stop(): none of the `count` samples counts as forwarded, each is write_failed and in the sink's log.
    void expect_every_sample_write_failed(std::uint64_t count) {
        const TopicCounters total = sut->total_counters();
        EXPECT_EQ(total.forwarded, 0u);
        EXPECT_EQ(total.forwarded_payload_bytes, 0u);
        EXPECT_EQ(total.forwarded_wire_bytes, 0u);
        EXPECT_EQ(total.dropped_for(DropReason::write_failed), count);
        EXPECT_TRUE(total.balanced());
        EXPECT_EQ(sink.dropped_count(DropReason::write_failed), count);
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
    EXPECT_EQ(sink.departure_threads(), std::vector<std::thread::id>{std::this_thread::get_id()});
}

TEST_F(ForwardingLoopTest, SendsARepairFromItsOwnThreadNotTheSubmittingOne) {
    make_sut(1e9);
    const std::thread::id submitter = std::this_thread::get_id();
    sut->submit_repair(Repair{7, topic, clock.now() + seconds(5), 8 * 200});
    ASSERT_TRUE(sink.wait_for_departures(1, milliseconds(5000)));
    EXPECT_EQ(sink.departures(), (std::vector<std::string>{"repair 7"}));
    EXPECT_NE(sink.departure_threads().front(), submitter)
        << "Fast DDS's thread submits it holding its writer's lock; the loop's thread writes";
    EXPECT_EQ(sut->repair_counters().sent, 1u);
}

TEST_F(ForwardingLoopTest, DiscardsARepairSubmittedAfterStop) {
    make_sut(1e9);
    sut->stop();
    sut->submit_repair(Repair{7, topic, clock.now() + seconds(5), 8 * 200});
    EXPECT_TRUE(sink.departures().empty());
    EXPECT_EQ(sink.discarded_repairs(), (std::vector<std::uint64_t>{7}));
}

TEST_F(ForwardingLoopTest, ReleasesQueuedSamplesAsTheLinkDrains) {
    make_sut(2'000'000);  // 1,600 wire bits each: 0.8 ms apiece
    for (int i = 0; i < 50; ++i)
        sut->submit(sample(100));
    EXPECT_TRUE(sink.wait_for_forwarded(50, milliseconds(5'000)));
}

/// An idle source that has `available` samples at a time; more when given().
class GivenIdleSource final : public IdleSource {
  public:
    std::optional<Sample> next_when_idle(base::SteadyTime /*now*/) override {
        std::lock_guard<std::mutex> lock(mutex_);
        if (available_ == 0)
            return std::nullopt;
        --available_;
        Sample s;
        s.payload.assign(100, 7);
        return s;
    }
    std::optional<base::SteadyTime> next_ready(base::SteadyTime now) const override {
        std::lock_guard<std::mutex> lock(mutex_);
        return available_ > 0 ? std::optional<base::SteadyTime>(now) : std::nullopt;
    }
    void give(int n) {
        std::lock_guard<std::mutex> lock(mutex_);
        available_ += n;
    }

  private:
    mutable std::mutex mutex_;
    int available_ = 0;
};

TEST_F(ForwardingLoopTest, TheLoopsThreadSendsWhatTheIdleSourceHasAndWakesWhenKicked) {
    make_sut(2'000'000);
    const TopicId backfill = sut->add_topic({"tgw/backfill", seconds(3600)});
    GivenIdleSource source;
    source.give(20);
    sut->set_idle_source(&source, backfill);
    EXPECT_TRUE(sink.wait_for_forwarded(20, milliseconds(5'000))) << "no sample submitted: the loop's own thread";
    source.give(5);
    sut->kick();
    EXPECT_TRUE(sink.wait_for_forwarded(25, milliseconds(5'000)));
    EXPECT_EQ(sut->counters(backfill).forwarded, 25u);
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

TEST_F(ForwardingLoopTest, AWriteThatFailsAfterTheDecisionCountsAsWriteFailed) {
    make_sut(1e9);
    sink.refuse_writes();
    sut->submit(sample());
    sut->stop();
    expect_every_sample_write_failed(1);
}

TEST_F(ForwardingLoopTest, ABundleWhoseWriteFailsAfterTheDecisionCountsAsWriteFailed) {
    make_sut(1e9, true);
    sink.refuse_writes();
    sut->submit(sample());
    sut->submit(sample());
    sut->stop();
    expect_every_sample_write_failed(2);
}

// A sample too large for one bundle leaves in chunks, all decided before any is written: the sample has left
// (as far as the scheduler knows) by the time a write fails. It is logged whole, once, and counted write_failed.
TEST_F(ForwardingLoopTest, AChunkedSampleWhoseFirstChunkFailsAfterTheDecisionIsLoggedWhole) {
    make_sut(1e9, true);
    sink.refuse_writes(1);
    sut->submit(sample(6'000));
    sut->stop();
    const TopicCounters total = sut->total_counters();
    EXPECT_EQ(total.forwarded, 0u);
    EXPECT_EQ(total.forwarded_payload_bytes, 0u);
    EXPECT_EQ(total.dropped_for(DropReason::write_failed), 1u);
    EXPECT_TRUE(total.balanced());
    const std::vector<test::RecordingSink::Dropped> dropped = sink.dropped();
    ASSERT_EQ(dropped.size(), 1u);
    EXPECT_EQ(dropped[0].reason, DropReason::write_failed);
    EXPECT_EQ(dropped[0].sample.payload.size(), 6'000u) << "the whole sample, not a chunk";
    EXPECT_FALSE(dropped[0].sample.chunk);
}

TEST_F(ForwardingLoopTest, AChunkedSampleWhoseLastChunkFailsAfterTheDecisionIsLoggedWhole) {
    make_sut(1e9, true);
    sink.refuse_writes(1, 4);  // 6,000 bytes leave in 5 bundles of at most 1,284: the fifth fails
    sut->submit(sample(6'000));
    sut->stop();
    ASSERT_EQ(sink.bundles().size(), 5u);
    const TopicCounters total = sut->total_counters();
    EXPECT_EQ(total.forwarded, 0u);
    EXPECT_EQ(total.dropped_for(DropReason::write_failed), 1u);
    EXPECT_TRUE(total.balanced());
    const std::vector<test::RecordingSink::Dropped> dropped = sink.dropped();
    ASSERT_EQ(dropped.size(), 1u);
    EXPECT_EQ(dropped[0].sample.payload.size(), 6'000u);
}

/// A sink whose first forward blocks until open() is called, as a WAN write on a full socket does.
class BlockingSink final : public SampleSink {
  public:
    bool forward(Sample&& sample) override {
        block_the_first();
        return inner.forward(std::move(sample));
    }
    std::size_t forward_bundle(std::vector<Sample>&& samples, std::size_t wire_bytes) override {
        block_the_first();
        return inner.forward_bundle(std::move(samples), wire_bytes);
    }
    void drop(Sample&& sample, DropReason reason) override { inner.drop(std::move(sample), reason); }

    void wait_until_blocked() {
        std::unique_lock<std::mutex> lock(mutex_);
        changed_.wait(lock, [this] { return first_started_; });
    }
    void open() {
        std::lock_guard<std::mutex> lock(mutex_);
        open_ = true;
        changed_.notify_all();
    }

    test::RecordingSink inner;

  private:
    void block_the_first() {
        std::unique_lock<std::mutex> lock(mutex_);
        if (!first_started_) {
            first_started_ = true;
            changed_.notify_all();
            changed_.wait(lock, [this] { return open_; });
        }
    }

    std::mutex mutex_;
    std::condition_variable changed_;
    bool first_started_ = false;
    bool open_ = false;
};

// Before the decisions were written after the lock, a listener bringing a sample waited for every WAN write
// in progress, and its reader's history filled meanwhile. In both WAN modes: a bundle is one write.
class ForwardingLoopWritesTest : public ::testing::TestWithParam<bool> {};

TEST_P(ForwardingLoopWritesTest, AListenerIsNotHeldUpByAWanWriteThatBlocks) {
    base::SystemClock clock;
    BlockingSink sink;
    SchedulerConfig config;
    config.initial_rate_bps = 1e9;
    if (GetParam()) {
        config.bundles = BundleLimits{};
    }
    ForwardingLoop sut(config, clock, sink);
    const TopicId topic = sut.add_topic({"A", seconds(5)});
    sut.start();
    const auto sample = [&](std::uint8_t fill) {
        Sample s;
        s.topic = topic;
        s.payload.assign(64, fill);
        s.source_time = clock.wall_now();
        return s;
    };

    std::thread writer([&] { sut.submit(sample(1)); });  // admitted at once, and its write blocks
    sink.wait_until_blocked();
    auto second = std::async(std::launch::async, [&] { sut.submit(sample(2)); });
    const bool returned = second.wait_for(seconds(10)) == std::future_status::ready;
    sink.open();
    writer.join();
    second.get();
    sut.stop();

    EXPECT_TRUE(returned) << "submit() waited for another thread's WAN write";
    const std::vector<Sample> forwarded = sink.inner.forwarded();
    ASSERT_EQ(forwarded.size(), 2u);
    EXPECT_EQ(forwarded[0].payload[0], 1) << "written in the order decided";
    EXPECT_EQ(forwarded[1].payload[0], 2);
    EXPECT_EQ(sut.total_counters().forwarded, 2u);
}

/// A sink whose writes put `extra_bits` more on the link than the scheduler charged, as a reliable WAN writer's
/// HEARTBEAT does, and charge them to the loop from within the write.
class ChargingSink final : public SampleSink {
  public:
    bool forward(Sample&& sample) override {
        if (loop != nullptr) {
            charged_from_write.push_back(loop->charge_link_from_write(extra_bits));
        }
        return inner.forward(std::move(sample));
    }
    std::size_t forward_bundle(std::vector<Sample>&& samples, std::size_t wire_bytes) override {
        return inner.forward_bundle(std::move(samples), wire_bytes);
    }
    void drop(Sample&& sample, DropReason reason) override { inner.drop(std::move(sample), reason); }

    ForwardingLoop* loop = nullptr;
    std::uint64_t extra_bits = 0;
    std::vector<bool> charged_from_write;  ///< the writing thread's alone
    test::RecordingSink inner;
};

TEST(ForwardingLoopChargeTest, WhatAWriteAddsIsChargedBeforeTheNextDecisionByTheWritingThread) {
    base::SystemClock clock;
    ChargingSink sink;
    SchedulerConfig config;
    config.initial_rate_bps = 1e6;
    ForwardingLoop sut(config, clock, sink);
    const TopicId topic = sut.add_topic({"A", seconds(5)});
    sut.start();
    sink.loop = &sut;
    // Beyond the reserve's 1,000,000 bits (5 % of the rate saved over 20 s): the link is then busy for the
    // budget's bound, a second ahead.
    sink.extra_bits = 4'000'000;
    const auto sample = [&] {
        Sample s;
        s.topic = topic;
        s.payload.assign(100, 1);
        s.source_time = clock.wall_now();
        return s;
    };

    EXPECT_FALSE(sut.charge_link_from_write(8)) << "this thread writes none of the loop's decisions";
    sut.submit(sample());
    ASSERT_EQ(sink.inner.forwarded().size(), 1u);
    EXPECT_EQ(sink.charged_from_write, std::vector<bool>{true});
    sut.submit(sample());
    EXPECT_EQ(sut.queued_samples(), 1u) << "the first write's extra holds the link: charged before this decision";
    EXPECT_TRUE(sink.inner.wait_for_forwarded(2, milliseconds(5'000)));
    sut.stop();
    EXPECT_EQ(sut.total_counters().forwarded, 2u);
}

INSTANTIATE_TEST_SUITE_P(WanModes, ForwardingLoopWritesTest, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& info) {
                             return info.param ? "Compact" : "Standard";
                         });

}  // namespace
}  // namespace tgw::core
