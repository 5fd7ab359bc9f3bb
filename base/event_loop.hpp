// A thread of its own that runs tasks one at a time: those posted in order, timed ones when their time comes.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <thread>

namespace tgw::base {

/// What an object does in a thread of its own (the Gateway makes and deletes DDS entities there, never in Fast DDS's
/// callbacks) without a loop of its own: tasks posted from any thread run in the order posted, timed tasks once the
/// steady clock reaches their time, posted ones first. Tasks posted before start() wait for it.
class EventLoop {
  public:
    using Task = std::function<void()>;
    using TimePoint = std::chrono::steady_clock::time_point;

    EventLoop() = default;
    /// Stops.
    ~EventLoop();
    EventLoop(const EventLoop&) = delete;
    EventLoop& operator=(const EventLoop&) = delete;

    /// Starts the thread. Once only.
    void start();
    /// Runs `task` in the loop's thread, after those posted before it.
    void post(Task task);
    /// Runs `task` in the loop's thread once the steady clock reaches `at` (a real-time wait, whatever clock the
    /// caller's logic runs on).
    void post_at(TimePoint at, Task task);
    /// Runs `task` in the loop's thread `period` from now, and again `period` after each run ends, until stop().
    void post_every(std::chrono::steady_clock::duration period, Task task);
    /// Lets the task running finish, then ends the thread; the tasks still waiting never run. Idempotent, and from
    /// any thread but the loop's.
    void stop();

  private:
    void run();

    std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<Task> posted_;               // under mutex_
    std::multimap<TimePoint, Task> timed_;  // under mutex_
    bool stopping_ = false;                 // under mutex_
    std::thread thread_;
};

}  // namespace tgw::base
