#include "base/event_loop.hpp"

#include <utility>

namespace tgw::base {

EventLoop::~EventLoop() {
    stop();
}

void EventLoop::start() {
    thread_ = std::thread([this] { run(); });
}

void EventLoop::post(Task task) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        posted_.push_back(std::move(task));
    }
    changed_.notify_one();
}

void EventLoop::post_at(TimePoint at, Task task) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        timed_.emplace(at, std::move(task));
    }
    changed_.notify_one();
}

void EventLoop::post_every(std::chrono::steady_clock::duration period, Task task) {
    post_at(std::chrono::steady_clock::now() + period, [this, period, task = std::move(task)]() mutable {
        task();
        post_every(period, std::move(task));
    });
}

void EventLoop::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    changed_.notify_all();
    if (thread_.joinable()) {
        thread_.join();
    }
}

void EventLoop::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
        Task task;
        if (!posted_.empty()) {
            task = std::move(posted_.front());
            posted_.pop_front();
        } else if (!timed_.empty() && timed_.begin()->first <= std::chrono::steady_clock::now()) {
            task = std::move(timed_.begin()->second);
            timed_.erase(timed_.begin());
        } else if (!timed_.empty()) {
            changed_.wait_until(lock, timed_.begin()->first);
            continue;
        } else {
            changed_.wait(lock);
            continue;
        }
        lock.unlock();
        task();
        lock.lock();
    }
}

}  // namespace tgw::base
