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
    loop_.start();
    loop_.post_every(interval_, [this] { poll_once(); });
}

void RatePoller::stop() {
    loop_.stop();
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

}  // namespace tgw::dds
