// The scheduling core's operations with n samples already queued: the cost must grow as log n or better.
//
//   insert  Scheduler::push into a queue of n to 2n, the link stopped
//   pop     Scheduler::release sending one sample from a queue of n/2 to n, nothing pushed
//   admit   push one sample and release one from a queue holding n: the steady state of a backlogged gateway
//   memory  heap bytes per queued sample, beyond the payload's own allocation
//
// Each with the paper workload's 4 topics (TTL order 1, 2, 5, 20; stretched to hours so that nothing expires
// while the benchmark runs) and with 1000 topics of distinct TTLs; admit also under `edf`, where all topics
// share one rank and interleave by deadline.
#include <malloc.h>

#include <benchmark/benchmark.h>
#include <algorithm>
#include <string>
#include <vector>

#include "core/scheduler.hpp"

namespace {

using namespace tgw::base;
using namespace tgw::core;

constexpr std::size_t PAYLOAD_BYTES = 32;

class NullSink final : public SampleSink {
  public:
    bool forward(Sample&& s) override {
        benchmark::DoNotOptimize(s);
        return true;
    }
    std::size_t forward_bundle(std::vector<Sample>&& samples, std::size_t wire_bytes) override {
        benchmark::DoNotOptimize(samples);
        return wire_bytes;
    }
    void drop(Sample&& s, DropReason) override { benchmark::DoNotOptimize(s); }
};

struct Fixture {
    Fixture(std::int64_t queued, std::int64_t topic_count, PolicyKind policy) : scheduler(make_config(policy)) {
        static const int PAPER_TTL_HOURS[] = {1, 2, 5, 20};
        for (std::int64_t t = 0; t < topic_count; ++t) {
            const Duration ttl = topic_count == 4 ? Duration(std::chrono::hours(PAPER_TTL_HOURS[t]))
                                                  : Duration(std::chrono::hours(1) + std::chrono::seconds(t));
            topics.push_back(scheduler.add_topic({"t" + std::to_string(t), ttl}));
        }
        fill(queued);
    }
    static SchedulerConfig make_config(PolicyKind policy) {
        SchedulerConfig c;
        c.policy = policy;
        c.initial_rate_bps = 0.0;  // nothing leaves unless a benchmark raises the rate
        c.lead = Duration::zero();
        c.memory_cap_bytes = std::size_t{1} << 40;
        return c;
    }
    void push() {
        Sample s;
        s.topic = topics[static_cast<std::size_t>(next % static_cast<std::int64_t>(topics.size()))];
        s.payload.resize(PAYLOAD_BYTES);
        s.source_time = wall + std::chrono::microseconds(next);
        ++next;
        scheduler.push(std::move(s), now, wall, sink);
    }
    void fill(std::int64_t count) {
        for (std::int64_t i = 0; i < count; ++i)
            push();
    }
    /// Release exactly one sample per microsecond of `now`: a budget a little faster than that.
    void open_link() {
        scheduler.set_rate(1.01e6 * static_cast<double>(scheduler.config().wire.wire_bits(PAYLOAD_BYTES)) /
                           scheduler.config().budget_fraction);
    }
    void release_one() {
        now += std::chrono::microseconds(1);
        scheduler.release(now, sink);
    }

    Scheduler scheduler;
    NullSink sink;
    std::vector<TopicId> topics;
    std::int64_t next = 0;
    SteadyTime now{std::chrono::hours(1)};
    WallTime wall{std::chrono::hours(1)};
};

void set_counters(benchmark::State& state, const Fixture& f) {
    state.counters["queued"] = static_cast<double>(f.scheduler.queued_samples());
    state.counters["topics"] = static_cast<double>(f.topics.size());
    state.SetItemsProcessed(state.iterations());
}

void insert(benchmark::State& state) {
    Fixture f(state.range(0), state.range(1), PolicyKind::ttl);
    for (auto _ : state)
        f.push();
    set_counters(state, f);
}

void pop(benchmark::State& state) {
    const std::int64_t n = state.range(0);
    Fixture f(n, state.range(1), PolicyKind::ttl);
    f.open_link();
    for (auto _ : state) {
        if (f.scheduler.queued_samples() <= static_cast<std::size_t>(n / 2)) {
            state.PauseTiming();
            f.fill(n / 2);
            state.ResumeTiming();
        }
        f.release_one();
    }
    set_counters(state, f);
}

void admit(benchmark::State& state, PolicyKind policy) {
    Fixture f(state.range(0), state.range(1), policy);
    f.open_link();
    for (auto _ : state) {
        f.push();
        f.release_one();
    }
    set_counters(state, f);
}

std::size_t heap_in_use() {
    const struct mallinfo2 m = mallinfo2();
    return m.uordblks + m.hblkhd;
}

void memory(benchmark::State& state) {
    const std::int64_t n = state.range(0);
    // What n bare payloads take on the heap (the allocator's header and rounding included), to subtract.
    std::size_t payload_heap = 0;
    {
        std::vector<std::vector<std::uint8_t>> payloads(static_cast<std::size_t>(n));
        const std::size_t before = heap_in_use();
        for (auto& p : payloads)
            p.resize(PAYLOAD_BYTES);
        payload_heap = heap_in_use() - before;
    }
    std::size_t queue_heap = 0;
    for (auto _ : state) {
        Fixture f(0, state.range(1), PolicyKind::ttl);
        const std::size_t before = heap_in_use();
        f.fill(n);
        queue_heap = heap_in_use() - before;
        benchmark::DoNotOptimize(f.scheduler.queued_samples());
    }
    const double per_sample = static_cast<double>(queue_heap) / static_cast<double>(n);
    const double payload_per_sample = static_cast<double>(payload_heap) / static_cast<double>(n);
    state.counters["topics"] = static_cast<double>(state.range(1));
    state.counters["heap_B/sample"] = per_sample;
    state.counters["payload_heap_B"] = payload_per_sample;
    state.counters["bookkeeping_B"] = per_sample - payload_per_sample;
    state.counters["declared_B"] = static_cast<double>(DeadlineQueue::BOOKKEEPING_BYTES);
}

void register_all() {
    const std::vector<std::int64_t> sizes{1'000, 10'000, 100'000, 1'000'000};
    const std::vector<std::int64_t> topic_counts{4, 1'000};
    for (std::int64_t topics : topic_counts) {
        for (std::int64_t n : sizes) {
            // Fixed iteration counts keep the queue between n and 2n (insert) or n/2 and n (pop).
            benchmark::RegisterBenchmark("insert", insert)
                ->Args({n, topics})
                ->Iterations(std::min<std::int64_t>(n, 200'000));
            benchmark::RegisterBenchmark("pop", pop)->Args({n, topics});
            benchmark::RegisterBenchmark("admit/ttl", admit, PolicyKind::ttl)->Args({n, topics});
            benchmark::RegisterBenchmark("admit/edf", admit, PolicyKind::edf)->Args({n, topics});
        }
    }
    for (std::int64_t topics : topic_counts) {
        for (std::int64_t n : {std::int64_t{100'000}, std::int64_t{1'000'000}})
            benchmark::RegisterBenchmark("memory", memory)->Args({n, topics})->Iterations(1);
    }
}

}  // namespace

int main(int argc, char** argv) {
    register_all();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv))
        return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
