#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>

#include "base/event_loop.hpp"
#include "sensor/rate_sensor.hpp"

namespace tgw::dds {

/// Reads the rate sensor every `interval` in a thread of its own (a base::EventLoop) and hands each good reading to
/// `apply` (the gateway's rate and link backlog). A failed reading keeps the last rate; the first failure is reported
/// once.
class RatePoller {
  public:
    RatePoller(sensor::RateSensor& sensor, std::function<void(const sensor::RateReading&)> apply,
               std::chrono::milliseconds interval);
    ~RatePoller();

    RatePoller(const RatePoller&) = delete;
    RatePoller& operator=(const RatePoller&) = delete;

    /// Reads once in the calling thread (so the rate is set before traffic), then starts the thread.
    void start();
    /// Ends the thread, a reading under way first. Idempotent.
    void stop();

    std::uint64_t failures() const { return failures_.load(); }

  private:
    void poll_once();

    sensor::RateSensor& sensor_;
    const std::function<void(const sensor::RateReading&)> apply_;
    const std::chrono::milliseconds interval_;
    std::atomic<std::uint64_t> failures_{0};
    base::EventLoop loop_;
};

}  // namespace tgw::dds
