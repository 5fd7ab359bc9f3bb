#pragma once

#include <string>

#include "sensor/netlink_handles.hpp"
#include "sensor/rate_sensor.hpp"

namespace tgw::sensor {

/// `qdisc:IFACE`: the rate of the kernel shaper at the root of an interface, read through rtnetlink on every
/// poll, so it follows `tc qdisc change` at once. Understands tbf (its rate) and htb (the sum of its top-level
/// classes' rates, which cannot borrow from one another). Reads the network namespace of the thread that built
/// it. Not thread-safe: one poller at a time.
class QdiscSensor final : public RateSensor {
  public:
    /// Throws base::ConfigError naming the interface when it does not exist or has no shaper we understand.
    explicit QdiscSensor(std::string interface);
    ~QdiscSensor() override;

    QdiscSensor(const QdiscSensor&) = delete;
    QdiscSensor& operator=(const QdiscSensor&) = delete;

    /// On failure (the interface or the shaper went away), ok is false and `error` says why.
    RateReading read() override;
    std::string describe() const override;

  private:
    std::string interface_;
    NlSocketPtr socket_;
};

}  // namespace tgw::sensor
