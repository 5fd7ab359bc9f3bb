#pragma once

#include <optional>
#include <string>

#include "sensor/netlink_handles.hpp"
#include "sensor/nl80211_station_parser.hpp"
#include "sensor/rate_sensor.hpp"

namespace tgw::sensor {

/// `nl80211:IFACE[:PEER_MAC]`: the transmit bit rate the wireless driver uses towards the peer station, with its
/// signal strength, from an NL80211_CMD_GET_STATION dump on every poll (the modern iwspy / SIOCGIWRATE). Without
/// PEER_MAC the interface must have exactly one station: in station mode, the access point it is associated with.
/// Reads the network namespace of the thread that built it. Not thread-safe: one poller at a time.
class Nl80211Sensor final : public RateSensor {
  public:
    /// Throws base::ConfigError naming the interface when it does not exist, or is not a wireless interface (the
    /// kernel has no nl80211, or nl80211 does not know the interface). Not being associated yet is no error: the
    /// readings fail until it is.
    Nl80211Sensor(std::string interface, std::optional<MacAddress> peer);
    ~Nl80211Sensor() override;

    Nl80211Sensor(const Nl80211Sensor&) = delete;
    Nl80211Sensor& operator=(const Nl80211Sensor&) = delete;

    /// On failure ok is false and `error` names the interface and says why; never blocks longer than about 1 s.
    RateReading read() override;
    std::string describe() const override;

  private:
    struct Dump;

    /// Opens the generic netlink socket and resolves nl80211; "" or why not.
    std::string connect();
    /// One station dump; its error is "" on success, else the libnl error code is in `nl_error`.
    Dump dump_stations(int ifindex);

    std::string interface_;
    std::optional<MacAddress> peer_;
    NlSocketPtr socket_;
    int family_ = -1;
};

}  // namespace tgw::sensor
