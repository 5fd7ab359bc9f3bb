#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sensor/rate_sensor.hpp"

struct nl_msg;

namespace tgw::sensor {

/// A station's hardware address, as nl80211 sends it in NL80211_ATTR_MAC.
using MacAddress = std::array<std::uint8_t, 6>;

/// Parses "aa:bb:cc:dd:ee:ff" (either case, `:` or `-` between the octets); nullopt for anything else.
std::optional<MacAddress> parse_mac(std::string_view text);

/// "aa:bb:cc:dd:ee:ff", lower case.
std::string mac_text(const MacAddress& mac);

/// What the sensor needs from one station of an NL80211_CMD_GET_STATION dump.
struct StationInfo {
    MacAddress mac{};
    /// NL80211_STA_INFO_TX_BITRATE: BITRATE32, else the 16-bit BITRATE, in bit/s. Absent when the driver does
    /// not know it (or reports 0, which no link carries).
    std::optional<double> tx_bitrate_bps;
    /// NL80211_STA_INFO_SIGNAL (last frame), else NL80211_STA_INFO_SIGNAL_AVG, in dBm.
    std::optional<int> signal_dbm;
};

/// One station message parsed, or why it could not be.
struct StationParseResult {
    bool ok = false;
    StationInfo station;
    std::string error;  ///< when !ok: "truncated ...", "malformed ...", "no NL80211_ATTR_MAC ..."
};

/// Parses one reply of an NL80211_CMD_GET_STATION dump (command NL80211_CMD_NEW_STATION): the whole netlink
/// message, `size` bytes from its nlmsghdr. Checks every length against `size` and the attribute layout, so any
/// bytes are safe to feed it. Never throws.
StationParseResult parse_station_message(const void* data, std::size_t size);

/// The same for a libnl message (its nlmsghdr and nlmsg_len).
StationParseResult parse_station_message(nl_msg* message);

/// The reading for `interface` from the stations of one dump: the station `peer` when given, otherwise the only
/// station (in station mode, the access point it is associated with). ok is false, with `error` naming the
/// interface, when that station is absent, several stations leave the choice open, or it has no transmit rate.
/// `detail` carries the signal and the station: "signal -52 dBm, station aa:bb:cc:dd:ee:ff".
RateReading station_reading(const std::vector<StationInfo>& stations, const std::optional<MacAddress>& peer,
                            const std::string& interface);

}  // namespace tgw::sensor
