// EventLoop: tasks in order in a thread of their own, timed ones at their time, nothing after stop.
#include "base/event_loop.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <future>
#include <thread>
#include <vector>

namespace tgw::base {
namespace {

using namespace std::chrono_literals;

TEST(EventLoopTest, RunsPostedTasksInTheirOrderInAThreadOfItsOwn) {
    EventLoop loop;
    std::vector<int> order;
    std::promise<std::thread::id> ran_in;
    for (int i = 0; i < 5; ++i)
        loop.post([&order, i] { order.push_back(i); });
    loop.post([&] { ran_in.set_value(std::this_thread::get_id()); });
    loop.start();
    const std::thread::id loop_thread = ran_in.get_future().get();
    loop.stop();
    EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4})) << "posted before start, run after it, in order";
    EXPECT_NE(loop_thread, std::this_thread::get_id());
}

TEST(EventLoopTest, RunsTimedTasksByTheirTimeAndPostedOnesFirst) {
    EventLoop loop;
    std::vector<int> order;
    std::promise<void> done;
    const auto now = std::chrono::steady_clock::now();
    loop.post_at(now + 60ms, [&] {
        order.push_back(3);
        done.set_value();
    });
    loop.post_at(now + 30ms, [&] { order.push_back(2); });
    loop.post_at(now - 1ms, [&] { order.push_back(1); });  // due already: after what was posted
    loop.post([&] { order.push_back(0); });
    loop.start();
    done.get_future().wait();
    loop.stop();
    EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3}));
    EXPECT_GE(std::chrono::steady_clock::now() - now, 60ms) << "the last ran no earlier than its time";
}

TEST(EventLoopTest, StopLetsTheRunningTaskFinishAndRunsNothingMore) {
    EventLoop loop;
    std::promise<void> started;
    std::atomic<bool> finished{false};
    std::atomic<int> after{0};
    loop.post([&] {
        started.set_value();
        std::this_thread::sleep_for(50ms);
        finished = true;
    });
    loop.post([&] { ++after; });
    loop.post_at(std::chrono::steady_clock::now() + 10ms, [&] { ++after; });
    loop.start();
    started.get_future().wait();
    loop.stop();
    EXPECT_TRUE(finished.load());
    EXPECT_EQ(after.load(), 0);
    loop.stop();  // idempotent
}

TEST(EventLoopTest, RunsAPeriodicTaskAPeriodAfterEachRunUntilStopped) {
    EventLoop loop;
    std::vector<std::chrono::steady_clock::time_point> runs;
    std::promise<void> third;
    const auto start = std::chrono::steady_clock::now();
    loop.post_every(20ms, [&] {
        runs.push_back(std::chrono::steady_clock::now());
        if (runs.size() == 3)
            third.set_value();
    });
    loop.start();
    third.get_future().wait();
    loop.stop();
    ASSERT_EQ(runs.size(), 3u) << "nothing after stop";
    EXPECT_GE(runs[0] - start, 20ms) << "the first a period from the post";
    EXPECT_GE(runs[1] - runs[0], 20ms);
    EXPECT_GE(runs[2] - runs[1], 20ms);
}

TEST(EventLoopTest, ALoopNeverStartedStopsAtOnce) {
    EventLoop loop;
    loop.post([] { FAIL() << "never started, never run"; });
    loop.stop();
}

}  // namespace
}  // namespace tgw::base
