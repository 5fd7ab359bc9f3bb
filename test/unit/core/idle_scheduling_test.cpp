// The scheduler's idle source (backfill): what it hands out goes only when no live sample wants the link, and
// never costs a live sample its deadline.
#include <deque>

#include "test/unit/core/scheduler_fixture.hpp"

namespace tgw::core {
namespace {

using namespace std::chrono_literals;

/// Hands out samples of `payload_bytes`, as many as it was given, each stamped with its number in `route`.
class CountingIdleSource final : public IdleSource {
  public:
    CountingIdleSource(std::size_t samples, std::size_t payload_bytes, const test::FakeClock& clock)
        : left_(samples), payload_bytes_(payload_bytes), clock_(clock) {}

    std::optional<Sample> next_when_idle(base::SteadyTime /*now*/) override {
        ++asked;
        if (left_ == 0)
            return std::nullopt;
        --left_;
        Sample sample;
        sample.payload.assign(payload_bytes_, 0xBF);
        sample.route = static_cast<std::uint16_t>(++handed);
        sample.source_time = clock_.wall_now() - 1h;  // its own source time: long past
        return sample;
    }
    std::optional<base::SteadyTime> next_ready(base::SteadyTime now) const override {
        return left_ > 0 ? std::optional<base::SteadyTime>(now) : std::nullopt;
    }

    int asked = 0;
    int handed = 0;

  private:
    std::size_t left_;
    const std::size_t payload_bytes_;
    const test::FakeClock& clock_;
};

/// Remembers when each sample left, and what it was, to tell when it arrived.
class TimedSink final : public SampleSink {
  public:
    explicit TimedSink(const test::FakeClock& clock) : clock_(clock) {}
    struct Departure {
        TopicId topic;
        std::uint16_t route;
        std::size_t payload_bytes;
        base::SteadyTime at;
    };
    bool forward(Sample&& sample) override {
        departures.push_back({sample.topic, sample.route, sample.payload.size(), clock_.now()});
        return true;
    }
    std::size_t forward_bundle(std::vector<Sample>&& samples, std::size_t wire_bytes) override {
        for (const Sample& sample : samples) {
            if (sample.completes_sample())
                departures.push_back({sample.topic, sample.route, sample.payload.size(), clock_.now()});
            else
                ++chunks_before_last;
        }
        return wire_bytes;
    }
    void drop(Sample&& sample, DropReason reason) override { dropped.emplace_back(sample.topic, reason); }

    std::vector<Departure> departures;
    std::vector<std::pair<TopicId, DropReason>> dropped;
    int chunks_before_last = 0;

  private:
    const test::FakeClock& clock_;
};

class IdleSchedulingTest : public SchedulerFixture {
  protected:
    /// The paper's four topics and a backfill topic with an hour's TTL, at `rate_bps`; samples go into `timed`.
    void make(double rate_bps) {
        make_sut(PolicyKind::ttl, rate_bps);
        backfill = sut->add_topic({"tgw/backfill", 1h});
    }
    void push_live(TopicId topic, std::size_t bytes) {
        Sample s;
        s.topic = topic;
        s.payload.assign(bytes, static_cast<std::uint8_t>(topic));
        s.source_time = clock.wall_now();
        sut->push(std::move(s), clock.now(), clock.wall_now(), timed);
        pushed_at.push_back(clock.now());
    }
    void release_timed() { sut->release(clock.now(), timed); }
    void run_timed_for(base::Duration span) { run_for(span, timed); }
    base::Duration wire_time(std::size_t payload_bytes) const {
        return base::from_seconds(static_cast<double>(config.wire.wire_bits(payload_bytes)) / sut->rate_bps());
    }

    TimedSink timed{clock};
    TopicId backfill = 0;
    std::vector<base::SteadyTime> pushed_at;
};

TEST_F(IdleSchedulingTest, NothingIdleGoesWhileALiveSampleIsQueued) {
    make(10'000);
    CountingIdleSource source(100, 200, clock);
    sut->set_idle_source(&source, backfill);
    for (TopicId topic : {d, c, b, a, a, b})
        push_live(topic, 300);
    run_timed_for(10s);
    ASSERT_GE(timed.departures.size(), 8u);
    for (std::size_t i = 0; i < 6; ++i)
        EXPECT_NE(timed.departures[i].topic, backfill) << "departure " << i << ": a live sample was queued";
    for (std::size_t i = 6; i < timed.departures.size(); ++i)
        EXPECT_EQ(timed.departures[i].topic, backfill) << "departure " << i;
    EXPECT_EQ(sut->queued_samples(), 0u) << "one at a time: the next only once the link is free";
}

TEST_F(IdleSchedulingTest, TheIdleSourceFillsTheLinkOneSampleAtATimeAtTheBudget) {
    make(10'000);
    CountingIdleSource source(1000, 200, clock);
    sut->set_idle_source(&source, backfill);
    run_timed_for(10s);
    // 10 s at 10,000 bit/s, a sample's wire time apart: the link kept busy, never more.
    const auto expected = static_cast<std::size_t>(10s / wire_time(200));
    EXPECT_NEAR(static_cast<double>(timed.departures.size()), static_cast<double>(expected), 1.0);
    for (std::size_t i = 1; i < timed.departures.size(); ++i)
        EXPECT_GE(timed.departures[i].at - timed.departures[i - 1].at, wire_time(200));
    EXPECT_EQ(sut->counters(backfill).forwarded, timed.departures.size());
}

TEST_F(IdleSchedulingTest, HazardsThatComeWhileBackfillFillsTheLinkKeepTheirDeadline) {
    // 20,000 bit/s, backfill rows of 700 bytes (0.35 s of wire), a hazard (A, TTL 1 s, 41 bytes: 0.1 s) every
    // 200 ms.
    make(20'000);
    CountingIdleSource source(1000, 700, clock);
    sut->set_idle_source(&source, backfill);
    for (int i = 0; i < 100; ++i) {
        push_live(a, 41);
        run_timed_for(200ms);
    }
    run_timed_for(2s);
    std::size_t hazards = 0;
    for (const TimedSink::Departure& departure : timed.departures) {
        if (departure.topic != a)
            continue;
        const base::SteadyTime arrived = departure.at + wire_time(departure.payload_bytes);
        EXPECT_LE(arrived - pushed_at[hazards], 1s) << "hazard " << hazards;
        ++hazards;
    }
    EXPECT_EQ(hazards, 100u);
    EXPECT_TRUE(timed.dropped.empty());
    EXPECT_GT(sut->counters(backfill).forwarded, 10u) << "backfill used the link between the hazards";
}

TEST_F(IdleSchedulingTest, ARowLongerThanTheHazardsRoomWaitsUntilTheHazardsStop) {
    // 1,500 bytes at 10,000 bit/s is 1.2 s of wire: longer than a hazard's TTL, it would cost one its deadline.
    make(10'000);
    CountingIdleSource source(1, 1500, clock);
    sut->set_idle_source(&source, backfill);
    for (int i = 0; i < 20; ++i) {
        push_live(a, 41);
        run_timed_for(200ms);
    }
    for (const TimedSink::Departure& departure : timed.departures)
        EXPECT_NE(departure.topic, backfill) << "while the hazards came";
    EXPECT_EQ(timed.departures.size(), 20u);
    const base::SteadyTime last_hazard = pushed_at.back();
    run_timed_for(3s);
    ASSERT_EQ(timed.departures.size(), 21u);
    EXPECT_EQ(timed.departures.back().topic, backfill);
    EXPECT_LE(timed.departures.back().at - last_hazard, 1s + 1ms) << "as soon as the hazards' topic went quiet";
    EXPECT_TRUE(timed.dropped.empty());
}

TEST_F(IdleSchedulingTest, InCompactModeARowLongerThanTheHazardsRoomGoesInChunksBetweenThem) {
    config.bundles = BundleLimits{};
    make(20'000);
    CountingIdleSource source(1, 6000, clock);  // 2.4 s of wire whole
    sut->set_idle_source(&source, backfill);
    for (int i = 0; i < 40; ++i) {
        push_live(a, 41);
        run_timed_for(200ms);
    }
    run_timed_for(2s);
    std::size_t hazards = 0;
    bool backfilled = false;
    for (const TimedSink::Departure& departure : timed.departures) {
        backfilled = backfilled || departure.topic == backfill;
        if (departure.topic == a) {
            EXPECT_LE(departure.at - pushed_at[hazards], 1s) << "hazard " << hazards << " left too late";
            ++hazards;
        }
    }
    EXPECT_EQ(hazards, 40u);
    EXPECT_TRUE(backfilled) << "its last chunk left; chunks before: " << timed.chunks_before_last
                            << ", queued: " << sut->queued_samples() << ", asked " << source.asked;
    EXPECT_GT(timed.chunks_before_last, 0);
    EXPECT_TRUE(timed.dropped.empty());
}

TEST_F(IdleSchedulingTest, NothingIsAskedForWhileTheIdleTopicIsUnreachable) {
    make(10'000);
    CountingIdleSource source(10, 200, clock);
    sut->set_idle_source(&source, backfill);
    sut->set_reachable(backfill, false);
    run_timed_for(5s);
    EXPECT_EQ(source.asked, 0) << "no camp reader of backfill: its rows stay in the source";
    EXPECT_FALSE(sut->next_wakeup(clock.now()));
    sut->set_reachable(backfill, true);
    EXPECT_EQ(sut->next_wakeup(clock.now()), clock.now());
    run_timed_for(5s);
    EXPECT_EQ(timed.departures.size(), 10u);
}

TEST_F(IdleSchedulingTest, TheLoopWakesWhenTheLinkIsFreeForTheNextIdleSample) {
    make(10'000);
    CountingIdleSource source(10, 200, clock);
    sut->set_idle_source(&source, backfill);
    release_timed();
    ASSERT_EQ(timed.departures.size(), 1u);
    EXPECT_EQ(sut->next_wakeup(clock.now()), clock.now() + wire_time(200));
}

TEST_F(IdleSchedulingTest, NothingIsAskedForAtARateOfZero) {
    make(0);
    CountingIdleSource source(10, 200, clock);
    sut->set_idle_source(&source, backfill);
    run_timed_for(5s);
    EXPECT_EQ(source.asked, 0);
    EXPECT_FALSE(sut->next_wakeup(clock.now()));
}

}  // namespace
}  // namespace tgw::core
