#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "base/clock.hpp"
#include "sensor/delivered_rate_estimator.hpp"
#include "sensor/guarded_sensor.hpp"
#include "sensor/link_counter_reader.hpp"
#include "sensor/rate_sensor.hpp"

namespace tgw::sensor {

/// Where the check's counters come from: the kernel's (LinkCounterReader::read in the gateway, scripted in
/// tests) and the cumulative bytes the gateway wrote, as its wire model counts them.
struct DeliveredRateSources {
    std::function<KernelCountersReading()> kernel;
    /// Empty: take the interface's own transmit counter (tm-sense, which sends nothing itself).
    std::function<std::uint64_t()> sent_bytes;
};

/// The delivered-rate check on top of any sensor: each reading of the inner sensor is compared with what the
/// link really carried (DeliveredRateEstimator over the kernel's counters), and the rate passed on is capped
/// below the sensor's claim while the link drops or queues. The qdisc backlog is passed on as queued_bytes
/// when the inner sensor has no view of it, so the scheduler waits for a standing queue to drain. A failing
/// counter read passes the sensor's rate through. Starting and ending a cap, and a counter failure, are each
/// logged once. Not thread-safe.
class DeliveredRateCheck final : public RateSensor {
  public:
    /// `clock` must outlive the check; `log` may be empty. Throws base::ConfigError when `config` is invalid or
    /// `sources.kernel` is empty.
    DeliveredRateCheck(std::unique_ptr<RateSensor> inner, DeliveredRateSources sources, DeliveredRateConfig config,
                       const base::Clock& clock, SensorLog log);

    /// The inner sensor's reading with its rate capped where the link delivers less; `detail` gains the
    /// delivered rate and the cap.
    RateReading read() override;
    /// The inner sensor's SPEC, plus "+delivered-check".
    std::string describe() const override;

    std::optional<double> cap_bps() const { return estimator_.cap_bps(); }
    LinkVerdict verdict() const { return estimator_.verdict(); }

  private:
    void log(SensorLogLevel level, const std::string& message) const;
    void note_counter_failure(const std::string& error);
    void note_cap(double claimed_bps);

    std::unique_ptr<RateSensor> inner_;
    DeliveredRateSources sources_;
    DeliveredRateEstimator estimator_;
    SensorLog log_;
    std::string counter_failure_;  ///< the current counter failure, "" when none
    bool capping_ = false;
};

/// The sources for `interface` in the caller's network namespace: a LinkCounterReader (shared by the
/// returned function) and `sent_bytes`. Throws base::ConfigError naming the interface when it does not exist.
DeliveredRateSources kernel_sources(const std::string& interface, std::function<std::uint64_t()> sent_bytes);

}  // namespace tgw::sensor
