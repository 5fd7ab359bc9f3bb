#pragma once

#include <string>

#include "sensor/rate_sensor.hpp"

namespace tgw::sensor {

/// `fixed:BPS`: a link whose rate is known and constant. Every reading succeeds with that rate.
class FixedSensor final : public RateSensor {
  public:
    explicit FixedSensor(double rate_bps);

    RateReading read() override;
    std::string describe() const override;

  private:
    double rate_bps_;
};

}  // namespace tgw::sensor
