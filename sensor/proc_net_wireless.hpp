#pragma once

#include <istream>
#include <string>
#include <vector>

namespace tgw::sensor {

/// One interface line of /proc/net/wireless (wireless extensions), e.g.
/// ` wlan0: 0000   54.  -56.  -256        0      0      0      0      0        0`.
struct WirelessStatus {
    std::string interface;
    double link_quality = 0.0;  ///< the driver's link quality, commonly out of 70 (iw_range max_qual)
    double level_dbm = 0.0;     ///< signal level
    double noise_dbm = 0.0;     ///< noise level; -256 when the driver does not know it
};

/// The interfaces /proc/net/wireless lists, or why the text could not be read.
struct WirelessTable {
    bool ok = false;
    std::vector<WirelessStatus> interfaces;
    std::string error;  ///< when !ok: "line N: what is wrong"
};

/// Parses the text of /proc/net/wireless: lines with a `NAME:` are interfaces, the others (the two header lines)
/// are skipped. The kernel marks updated values with a trailing '.', which is ignored. Never throws: it runs on
/// every poll.
WirelessTable parse_proc_net_wireless(std::istream& in);

}  // namespace tgw::sensor
