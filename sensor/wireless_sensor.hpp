#pragma once

#include <string>

#include "sensor/link_quality_table.hpp"
#include "sensor/rate_sensor.hpp"

namespace tgw::sensor {

/// `wireless:IFACE[:table=FILE]`: the link quality of IFACE from /proc/net/wireless (wireless extensions), mapped
/// to a rate through a LinkQualityTable (the built-in one without `table=`). Read afresh on every poll.
class WirelessSensor final : public RateSensor {
  public:
    /// The default for `proc_path`; tests give their own file.
    static constexpr const char* PROC_NET_WIRELESS = "/proc/net/wireless";

    /// Throws base::ConfigError naming the interface when `proc_path` cannot be read (no wireless extensions)
    /// or does not list it (not a wireless interface).
    WirelessSensor(std::string interface, LinkQualityTable table, std::string proc_path = PROC_NET_WIRELESS);

    /// Fails (ok false, `error` naming the interface) when the interface is no longer listed or its quality is
    /// below the table's first row. `detail`: "quality 54, signal -56 dBm".
    RateReading read() override;
    std::string describe() const override;

    /// What the factory appends to describe() for a table from a file.
    void set_table_name(std::string name) { table_name_ = std::move(name); }

  private:
    std::string interface_;
    LinkQualityTable table_;
    std::string proc_path_;
    std::string table_name_;
};

}  // namespace tgw::sensor
