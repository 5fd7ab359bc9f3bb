#pragma once

#include <string>

#include "base/clock.hpp"
#include "sensor/rate_sensor.hpp"
#include "sensor/rate_trace.hpp"

namespace tgw::sensor {

/// `trace:FILE`: replays a recorded or scripted rate. Time in the trace is measured on `clock` from the
/// sensor's construction; see RateTrace for what holds before the first and after the last step.
class TraceSensor final : public RateSensor {
  public:
    /// `clock` must outlive the sensor. `file_name` is only for describe().
    TraceSensor(RateTrace trace, std::string file_name, const base::Clock& clock);

    RateReading read() override;
    std::string describe() const override;

  private:
    RateTrace trace_;
    std::string file_name_;
    const base::Clock& clock_;
    base::SteadyTime start_;
};

}  // namespace tgw::sensor
