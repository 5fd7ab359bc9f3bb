// A Scheduler driven as the gateway's loop drives it, on a fake clock, into a RecordingSink, with the paper's four
// topics A to D: the fixture of the scheduler's tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>

#include "core/scheduler.hpp"
#include "test/fakes/fake_clock.hpp"
#include "test/fakes/recording_sink.hpp"

namespace tgw::core {

class SchedulerFixture : public ::testing::Test {
  protected:
    /// The scheduler with `config` as the test left it, at `rate_bps`, no lead and the whole rate to spend
    /// (exact arithmetic; the fraction has a test of its own).
    void make_sut(PolicyKind policy, double rate_bps) {
        config.policy = policy;
        config.initial_rate_bps = rate_bps;
        config.lead = base::Duration::zero();
        config.budget_fraction = 1.0;
        sut = std::make_unique<Scheduler>(config);
        a = sut->add_topic({"A", std::chrono::seconds(1)});
        b = sut->add_topic({"B", std::chrono::seconds(2)});
        c = sut->add_topic({"C", std::chrono::seconds(5)});
        d = sut->add_topic({"D", std::chrono::seconds(20)});
    }

    /// Pushes a sample of `payload_bytes` stamped `age` before now at the source. Its bytes are the topic's id,
    /// after a plain CDR encapsulation header when plain_cdr_payloads is set.
    void push(TopicId topic, std::size_t payload_bytes = 64, base::Duration age = base::Duration::zero()) {
        Sample s;
        s.topic = topic;
        s.payload.assign(payload_bytes, static_cast<std::uint8_t>(topic));
        if (plain_cdr_payloads) {
            std::fill_n(s.payload.begin(), std::min<std::size_t>(4, payload_bytes), 0);
            if (payload_bytes > 1)
                s.payload[1] = 1;
        }
        s.source_time = clock.wall_now() - std::chrono::duration_cast<base::WallClock::duration>(age);
        sut->push(std::move(s), clock.now(), clock.wall_now(), sink);
    }

    void release() { sut->release(clock.now(), sink); }

    /// Runs the scheduler as the gateway's loop would, in simulated time, for `span`, into `into` (the fixture's
    /// sink by default).
    void run_for(base::Duration span) { run_for(span, sink); }
    void run_for(base::Duration span, SampleSink& into) {
        const base::SteadyTime end = clock.now() + span;
        sut->release(clock.now(), into);
        while (auto next = sut->next_wakeup(clock.now())) {
            if (*next > end)
                break;
            clock.advance(std::max(*next - clock.now(), base::Duration(1)));
            sut->release(clock.now(), into);
        }
        if (clock.now() < end)
            clock.advance(end - clock.now());
    }

    /// `samples` of random topics and sizes (20 to 3,000 bytes), 0 to 40 ms apart, the rate changing at random
    /// (0 to 60,000 bit/s) every 500.
    void run_random_load(unsigned seed, int samples) {
        std::mt19937 rng(seed);
        std::uniform_int_distribution<int> topic(0, 3), size(20, 3'000), gap_ms(0, 40), rate(0, 60'000);
        for (int i = 0; i < samples; ++i) {
            push(static_cast<TopicId>(topic(rng)), static_cast<std::size_t>(size(rng)));
            if (i % 500 == 0)
                sut->set_rate(rate(rng));
            run_for(std::chrono::milliseconds(gap_ms(rng)));
        }
    }

    SchedulerConfig config;
    bool plain_cdr_payloads = false;
    test::FakeClock clock;
    test::RecordingSink sink;
    std::unique_ptr<Scheduler> sut;
    TopicId a = 0, b = 0, c = 0, d = 0;
};

}  // namespace tgw::core
