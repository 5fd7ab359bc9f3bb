#pragma once

#include <string>

#include "gateway/core/clock.hpp"
#include "sensor/rate_sensor.hpp"
#include "sensor/rate_trace.hpp"

namespace tgw::sensor {

/// `trace:FILE`: replays a recorded or scripted rate. Time in the trace is measured on `clock` from the
/// sensor's construction; see RateTrace for what holds before the first and after the last step.
class TraceSensor final : public RateSensor {
  public:
    /// `clock` must outlive the sensor. `file_name` is only for describe().
    TraceSensor(RateTrace trace, std::string file_name, const core::Clock& clock);

    RateReading read() override;
    std::string describe() const override;

  private:
    RateTrace trace_;
    std::string file_name_;
    const core::Clock& clock_;
    core::SteadyTime start_;
};

}  // namespace tgw::sensor
