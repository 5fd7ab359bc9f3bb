// The scheduling core's operations with n samples already queued: the cost must grow as log n or better.
#include <benchmark/benchmark.h>

#include "gateway/core/scheduler.hpp"

namespace {

using namespace tgw::core;

class NullSink final : public SampleSink {
  public:
    void forward(Sample&& s) override { benchmark::DoNotOptimize(s); }
    void drop(Sample&& s, DropReason) override { benchmark::DoNotOptimize(s); }
};

struct Fixture {
    explicit Fixture(std::int64_t queued, PolicyKind policy) : scheduler(make_config(policy)) {
        for (int t = 0; t < 4; ++t)
            topics.push_back(scheduler.add_topic({"t" + std::to_string(t), std::chrono::hours(1 + t)}));
        for (std::int64_t i = 0; i < queued; ++i)
            push(i);
    }
    static SchedulerConfig make_config(PolicyKind policy) {
        SchedulerConfig c;
        c.policy = policy;
        c.initial_rate_bps = 0.0;  // nothing leaves unless a test raises the rate
        c.lead = Duration::zero();
        c.memory_cap_bytes = std::size_t{1} << 40;
        return c;
    }
    void push(std::int64_t i) {
        Sample s;
        s.topic = topics[static_cast<std::size_t>(i) % topics.size()];
        s.payload.resize(32);
        s.source_time = wall + std::chrono::microseconds(i);
        scheduler.push(std::move(s), now, wall, sink);
    }
    Scheduler scheduler;
    NullSink sink;
    std::vector<TopicId> topics;
    SteadyTime now{std::chrono::hours(1)};
    WallTime wall{std::chrono::hours(1)};
};

/// One sample in and one out of a queue holding n: the steady state of a backlogged gateway.
void BM_PushAndRelease(benchmark::State& state) {
    Fixture f(state.range(0), PolicyKind::ttl);
    // One 32-byte sample's wire bits per microsecond: each step below releases exactly one sample.
    f.scheduler.set_rate(1e6 * static_cast<double>(f.scheduler.config().wire.wire_bits(32)));
    std::int64_t i = state.range(0);
    for (auto _ : state) {
        f.push(i++);
        f.now += std::chrono::microseconds(1);
        f.scheduler.release(f.now, f.sink);
    }
    state.counters["queued"] = static_cast<double>(f.scheduler.queued_samples());
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PushAndRelease)->RangeMultiplier(10)->Range(1'000, 1'000'000);

/// Push into a queue of n with the link stopped.
void BM_PushIntoQueue(benchmark::State& state) {
    Fixture f(state.range(0), PolicyKind::ttl);
    std::int64_t i = state.range(0);
    for (auto _ : state)
        f.push(i++);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PushIntoQueue)->RangeMultiplier(10)->Range(1'000, 1'000'000);

}  // namespace

BENCHMARK_MAIN();
