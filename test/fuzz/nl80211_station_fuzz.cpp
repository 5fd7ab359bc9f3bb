// A station dump comes from the kernel, but a driver's bug must not crash the gateway: any bytes give a station
// or an error, and a parsed rate is a rate.
#include <linux/nl80211.h>
#include <netlink/attr.h>
#include <netlink/genl/genl.h>
#include <netlink/msg.h>

#include <cmath>
#include <cstring>

#include "sensor/nl80211_station_parser.hpp"
#include "test/fuzz/fuzz_target.hpp"

namespace tgw::fuzz {

namespace {

/// One NL80211_CMD_NEW_STATION message as the kernel's nl80211_send_station() lays it out, built with libnl.
std::string station_message(bool bitrate32, bool bitrate16, bool signal) {
    nl_msg* message = nlmsg_alloc();
    genlmsg_put(message, NL_AUTO_PORT, NL_AUTO_SEQ, 0x1c, 0, NLM_F_MULTI, NL80211_CMD_NEW_STATION, 0);
    nla_put_u32(message, NL80211_ATTR_IFINDEX, 3);
    const std::uint8_t mac[6] = {0x02, 0, 0, 0, 1, 0};
    nla_put(message, NL80211_ATTR_MAC, sizeof mac, mac);
    nlattr* info = nla_nest_start(message, NL80211_ATTR_STA_INFO);
    nla_put_u32(message, NL80211_STA_INFO_INACTIVE_TIME, 120);
    if (signal)
        nla_put_u8(message, NL80211_STA_INFO_SIGNAL, static_cast<std::uint8_t>(-52));
    nlattr* rate = nla_nest_start(message, NL80211_STA_INFO_TX_BITRATE);
    if (bitrate16)
        nla_put_u16(message, NL80211_RATE_INFO_BITRATE, 540);
    nla_put_u8(message, NL80211_RATE_INFO_MCS, 7);
    if (bitrate32)
        nla_put_u32(message, NL80211_RATE_INFO_BITRATE32, 8667);
    nla_nest_end(message, rate);
    nla_nest_end(message, info);
    const nlmsghdr* header = nlmsg_hdr(message);
    std::string bytes(reinterpret_cast<const char*>(header), header->nlmsg_len);
    nlmsg_free(message);
    return bytes;
}

}  // namespace

std::vector<std::string> seeds() {
    return {station_message(true, true, true), station_message(false, true, true), station_message(true, false, false),
            station_message(false, false, true)};
}

}  // namespace tgw::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace tgw::sensor;
    // The parser reads headers in place, as it does from libnl's receive buffer: give it aligned memory.
    std::vector<std::uint32_t> aligned((size + 3) / 4);
    if (size > 0)
        std::memcpy(aligned.data(), data, size);
    const StationParseResult result = parse_station_message(aligned.data(), size);
    if (!result.ok) {
        TGW_FUZZ_CHECK(!result.error.empty());
        return 0;
    }
    if (result.station.tx_bitrate_bps)
        TGW_FUZZ_CHECK(std::isfinite(*result.station.tx_bitrate_bps) && *result.station.tx_bitrate_bps > 0.0);
    const RateReading reading = station_reading({result.station}, std::nullopt, "wlan0");
    TGW_FUZZ_CHECK(reading.ok == result.station.tx_bitrate_bps.has_value());
    TGW_FUZZ_CHECK(reading.ok ? reading.rate_bps > 0.0 : !reading.error.empty());
    return 0;
}
