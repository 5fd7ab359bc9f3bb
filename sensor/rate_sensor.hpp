#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "base/clock.hpp"

namespace tgw::sensor {

/// One reading of a link's data rate.
struct RateReading {
    bool ok = false;
    double rate_bps = 0.0;
    std::string detail;  ///< extra fields for people, e.g. "signal -52 dBm"; may be empty
    std::string error;   ///< why the reading failed, when !ok
    /// Bytes waiting in the link's queue now, where the sensor sees it (a kernel shaper's backlog): traffic the
    /// gateway did not schedule (discovery) or that the link did not carry as fast as the rate says.
    std::optional<std::uint64_t> queued_bytes;
    /// While the delivered-rate check holds the rate below the sensor's claim: the cap (rate_bps may be lower
    /// still, after the guard's margin).
    std::optional<double> cap_bps;
};

/// A reading that failed, saying why.
inline RateReading failed_reading(std::string error) {
    RateReading reading;
    reading.error = std::move(error);
    return reading;
}

/// Measures the data rate the link to the base camp can carry now. Polled by the gateway and by tm-sense.
class RateSensor {
  public:
    virtual ~RateSensor() = default;
    /// Never throws on the running path: a failure is a reading with ok == false.
    virtual RateReading read() = 0;
    /// The SPEC it was made from, for logs and status.
    virtual std::string describe() const = 0;
};

/// Builds a sensor from a SPEC of docs/design.md §6 (`fixed:BPS`, `trace:FILE`, ...). Throws base::ConfigError
/// naming the spec, file and line when it is malformed or the sensor cannot start.
std::unique_ptr<RateSensor> make_sensor(const std::string& spec, const base::Clock& clock);

}  // namespace tgw::sensor
