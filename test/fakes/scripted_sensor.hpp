#pragma once

#include <deque>
#include <string>
#include <utility>

#include "sensor/rate_sensor.hpp"

namespace tgw::test {

/// A rate sensor that returns readings a test lines up, in order; once they run out it repeats the last one
/// (a failure with "script empty" before any). Counts its reads.
class ScriptedSensor final : public sensor::RateSensor {
  public:
    explicit ScriptedSensor(std::string spec = "scripted:test") : spec_(std::move(spec)) {}

    /// Queues a good reading of `rate_bps`.
    ScriptedSensor& then_rate(double rate_bps, std::string detail = {}) {
        sensor::RateReading reading;
        reading.ok = true;
        reading.rate_bps = rate_bps;
        reading.detail = std::move(detail);
        script_.push_back(std::move(reading));
        return *this;
    }

    /// Queues a failed reading with `error`.
    ScriptedSensor& then_fail(std::string error) {
        sensor::RateReading reading;
        reading.error = std::move(error);
        script_.push_back(std::move(reading));
        return *this;
    }

    /// Queues any reading.
    ScriptedSensor& then(sensor::RateReading reading) {
        script_.push_back(std::move(reading));
        return *this;
    }

    sensor::RateReading read() override {
        ++reads_;
        if (!script_.empty()) {
            last_ = std::move(script_.front());
            script_.pop_front();
        }
        return last_;
    }

    std::string describe() const override { return spec_; }

    int reads() const { return reads_; }

  private:
    std::string spec_;
    std::deque<sensor::RateReading> script_;
    sensor::RateReading last_{false, 0.0, {}, "script empty", {}, {}};
    int reads_ = 0;
};

}  // namespace tgw::test
