#include "sensor/wireless_sensor.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "base/config_error.hpp"
#include "sensor/proc_net_wireless.hpp"

namespace tgw::sensor {

namespace {

std::string number_text(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

}  // namespace

WirelessSensor::WirelessSensor(std::string interface, LinkQualityTable table, std::string proc_path)
    : interface_(std::move(interface)), table_(std::move(table)), proc_path_(std::move(proc_path)) {
    if (interface_.empty())
        throw base::ConfigError("no interface given (wireless:IFACE[:table=FILE])");
    std::ifstream in(proc_path_);
    if (!in)
        throw base::ConfigError(interface_ + " is not a wireless interface: cannot read " + proc_path_ + " (" +
                                std::strerror(errno) + "; no wireless extensions in this kernel)");
    const WirelessTable listed = parse_proc_net_wireless(in);
    if (!listed.ok)
        throw base::ConfigError(proc_path_ + ": " + listed.error);
    for (const WirelessStatus& status : listed.interfaces) {
        if (status.interface == interface_)
            return;
    }
    throw base::ConfigError(interface_ + " is not a wireless interface: " + proc_path_ + " does not list it");
}

RateReading WirelessSensor::read() {
    try {
        std::ifstream in(proc_path_);
        if (!in)
            return failed_reading("cannot read " + proc_path_ + ": " + std::strerror(errno));
        const WirelessTable listed = parse_proc_net_wireless(in);
        if (!listed.ok)
            return failed_reading(proc_path_ + ": " + listed.error);
        for (const WirelessStatus& status : listed.interfaces) {
            if (status.interface != interface_)
                continue;
            std::string detail =
                "quality " + number_text(status.link_quality) + ", signal " + number_text(status.level_dbm) + " dBm";
            const auto rate = table_.rate_for(status.link_quality);
            if (!rate) {
                RateReading reading = failed_reading("link quality " + number_text(status.link_quality) + " of " +
                                                     interface_ + " is below the table's lowest row");
                reading.detail = std::move(detail);
                return reading;
            }
            RateReading reading;
            reading.ok = true;
            reading.rate_bps = *rate;
            reading.detail = std::move(detail);
            return reading;
        }
        return failed_reading(proc_path_ + " no longer lists " + interface_);
    } catch (const std::exception& e) {  // allocation only; never let a poll throw
        return failed_reading(e.what());
    }
}

std::string WirelessSensor::describe() const {
    return "wireless:" + interface_ + (table_name_.empty() ? "" : ":table=" + table_name_);
}

}  // namespace tgw::sensor
