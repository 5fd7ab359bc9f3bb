#include "sensor/trace_sensor.hpp"

#include <utility>

namespace tgw::sensor {

TraceSensor::TraceSensor(RateTrace trace, std::string file_name, const base::Clock& clock)
    : trace_(std::move(trace)), file_name_(std::move(file_name)), clock_(clock), start_(clock.now()) {}

RateReading TraceSensor::read() {
    RateReading reading;
    reading.ok = true;
    reading.rate_bps = trace_.rate_at(clock_.now() - start_);
    return reading;
}

std::string TraceSensor::describe() const {
    return "trace:" + file_name_;
}

}  // namespace tgw::sensor
