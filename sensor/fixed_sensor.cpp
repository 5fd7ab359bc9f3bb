#include "sensor/fixed_sensor.hpp"

#include <sstream>

namespace tgw::sensor {

FixedSensor::FixedSensor(double rate_bps) : rate_bps_(rate_bps) {}

RateReading FixedSensor::read() {
    RateReading reading;
    reading.ok = true;
    reading.rate_bps = rate_bps_;
    return reading;
}

std::string FixedSensor::describe() const {
    std::ostringstream out;
    out.precision(15);
    out << "fixed:" << rate_bps_;
    return out.str();
}

}  // namespace tgw::sensor
