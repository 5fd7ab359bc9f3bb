#include "gateway/dds/rate_poller.hpp"

#include <iostream>
#include <utility>

namespace tgw::dds {

RatePoller::RatePoller(sensor::RateSensor& sensor, std::function<void(const sensor::RateReading&)> apply,
                       std::chrono::milliseconds interval)
    : sensor_(sensor), apply_(std::move(apply)), interval_(interval) {}

RatePoller::~RatePoller() {
    stop();
}

void RatePoller::start() {
    poll_once();
    thread_ = std::thread([this] { run(); });
}

void RatePoller::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) {
        thread_.join();
    }
}

void RatePoller::poll_once() {
    const sensor::RateReading reading = sensor_.read();
    if (reading.ok) {
        apply_(reading);
        return;
    }
    if (failures_.fetch_add(1) == 0) {
        std::cerr << "telemetry-gateway: rate sensor " << sensor_.describe() << ": " << reading.error
                  << " (keeping the last rate; reported once)\n";
    }
}

void RatePoller::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!wake_.wait_for(lock, interval_, [this] { return stopping_; })) {
        lock.unlock();
        poll_once();
        lock.lock();
    }
}

}  // namespace tgw::dds
