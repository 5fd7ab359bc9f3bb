#include "sensor/nl80211_station_parser.hpp"

#include <linux/genetlink.h>
#include <linux/netlink.h>
#include <linux/nl80211.h>
#include <netlink/attr.h>
#include <netlink/msg.h>
#include <netlink/netlink.h>

#include <cstdio>
#include <cstring>

#include "base/hex.hpp"

namespace tgw::sensor {

namespace {

/// nl80211 reports rates in units of 100 kbit/s.
constexpr double BITRATE_UNIT_BPS = 100'000.0;

StationParseResult failure(std::string error) {
    StationParseResult result;
    result.error = std::move(error);
    return result;
}

/// Fills `table` (maxtype + 1 entries) from the attributes at `head`. libnl's nla_parse stops quietly at a
/// truncated attribute, so the leftover is checked here first: bytes that do not form a whole attribute mean the
/// message was cut. Returns an error text naming `what`, or "" when the attributes are well formed.
std::string parse_attributes(nlattr** table, int maxtype, nlattr* head, int length, nla_policy* policy,
                             const char* what) {
    const nlattr* attribute = nullptr;
    int remaining = 0;
    nla_for_each_attr(attribute, head, length, remaining) {}
    if (remaining > 0)
        return std::string("truncated ") + what + ": " + std::to_string(remaining) +
               " trailing bytes do not form an attribute";
    if (const int err = nla_parse(table, maxtype, head, length, policy); err < 0)
        return std::string("malformed ") + what + ": an attribute has the wrong length (" + nl_geterror(err) + ")";
    return {};
}

/// The transmit rate nested in NL80211_STA_INFO_TX_BITRATE, in bit/s; BITRATE32 first, as nl80211.h asks.
std::string parse_tx_bitrate(nlattr* nested, std::optional<double>& rate_bps) {
    nlattr* rate[NL80211_RATE_INFO_BITRATE32 + 1] = {};
    nla_policy policy[NL80211_RATE_INFO_BITRATE32 + 1] = {};
    policy[NL80211_RATE_INFO_BITRATE].type = NLA_U16;
    policy[NL80211_RATE_INFO_BITRATE32].type = NLA_U32;
    if (auto error = parse_attributes(rate, NL80211_RATE_INFO_BITRATE32, static_cast<nlattr*>(nla_data(nested)),
                                      nla_len(nested), policy, "NL80211_STA_INFO_TX_BITRATE");
        !error.empty())
        return error;
    std::uint32_t units = 0;
    if (rate[NL80211_RATE_INFO_BITRATE32] != nullptr)
        units = nla_get_u32(rate[NL80211_RATE_INFO_BITRATE32]);
    else if (rate[NL80211_RATE_INFO_BITRATE] != nullptr)
        units = nla_get_u16(rate[NL80211_RATE_INFO_BITRATE]);
    // 0 means the driver does not know the rate (some report it before the first frame); no link carries 0.
    if (units > 0)
        rate_bps = units * BITRATE_UNIT_BPS;
    return {};
}

std::string parse_station_info(nlattr* nested, StationInfo& station) {
    nlattr* info[NL80211_STA_INFO_SIGNAL_AVG + 1] = {};
    nla_policy policy[NL80211_STA_INFO_SIGNAL_AVG + 1] = {};
    policy[NL80211_STA_INFO_SIGNAL].type = NLA_U8;
    policy[NL80211_STA_INFO_SIGNAL_AVG].type = NLA_U8;
    policy[NL80211_STA_INFO_TX_BITRATE].type = NLA_NESTED;
    if (auto error = parse_attributes(info, NL80211_STA_INFO_SIGNAL_AVG, static_cast<nlattr*>(nla_data(nested)),
                                      nla_len(nested), policy, "NL80211_ATTR_STA_INFO");
        !error.empty())
        return error;
    // The kernel sends dBm as a u8 holding an s8.
    if (info[NL80211_STA_INFO_SIGNAL] != nullptr)
        station.signal_dbm = static_cast<std::int8_t>(nla_get_u8(info[NL80211_STA_INFO_SIGNAL]));
    else if (info[NL80211_STA_INFO_SIGNAL_AVG] != nullptr)
        station.signal_dbm = static_cast<std::int8_t>(nla_get_u8(info[NL80211_STA_INFO_SIGNAL_AVG]));
    if (info[NL80211_STA_INFO_TX_BITRATE] != nullptr)
        return parse_tx_bitrate(info[NL80211_STA_INFO_TX_BITRATE], station.tx_bitrate_bps);
    return {};
}

}  // namespace

std::optional<MacAddress> parse_mac(std::string_view text) {
    constexpr std::size_t TEXT_LENGTH = 17;  // six octets of two digits, five separators
    if (text.size() != TEXT_LENGTH)
        return std::nullopt;
    const char separator = text[2];
    if (separator != ':' && separator != '-')
        return std::nullopt;
    MacAddress mac{};
    for (std::size_t i = 0; i < mac.size(); ++i) {
        const std::size_t at = 3 * i;
        const int high = base::hex_digit(text[at]);
        const int low = base::hex_digit(text[at + 1]);
        if (high < 0 || low < 0 || (i + 1 < mac.size() && text[at + 2] != separator))
            return std::nullopt;
        mac[i] = static_cast<std::uint8_t>(high * 16 + low);
    }
    return mac;
}

std::string mac_text(const MacAddress& mac) {
    char buffer[18];
    std::snprintf(buffer, sizeof buffer, "%02x:%02x:%02x:%02x:%02x:%02x", mac[0], mac[1], mac[2], mac[3], mac[4],
                  mac[5]);
    return buffer;
}

StationParseResult parse_station_message(const void* data, std::size_t size) {
    if (data == nullptr || size < NLMSG_HDRLEN)
        return failure("truncated station message: " + std::to_string(size) + " bytes, less than a netlink header");
    // Copy the header: `data` need not be aligned for nlmsghdr.
    nlmsghdr header{};
    std::memcpy(&header, data, sizeof header);
    if (header.nlmsg_len < NLMSG_HDRLEN || header.nlmsg_len > size)
        return failure("truncated station message: its header says " + std::to_string(header.nlmsg_len) + " bytes, " +
                       std::to_string(size) + " arrived");
    if (header.nlmsg_len < NLMSG_HDRLEN + GENL_HDRLEN)
        return failure("truncated station message: no generic netlink header");
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    genlmsghdr genl{};
    std::memcpy(&genl, bytes + NLMSG_HDRLEN, sizeof genl);
    if (genl.cmd != NL80211_CMD_NEW_STATION)
        return failure("not a station message: nl80211 command " + std::to_string(genl.cmd));

    // nla_* read in place; attributes are 4-byte aligned in a message that starts aligned, as libnl's are.
    auto* head = reinterpret_cast<nlattr*>(const_cast<std::uint8_t*>(bytes) + NLMSG_HDRLEN + GENL_HDRLEN);
    const int length = static_cast<int>(header.nlmsg_len - NLMSG_HDRLEN - GENL_HDRLEN);
    nlattr* attributes[NL80211_ATTR_STA_INFO + 1] = {};
    nla_policy policy[NL80211_ATTR_STA_INFO + 1] = {};
    policy[NL80211_ATTR_MAC].minlen = policy[NL80211_ATTR_MAC].maxlen = sizeof(MacAddress);
    policy[NL80211_ATTR_STA_INFO].type = NLA_NESTED;
    if (auto error = parse_attributes(attributes, NL80211_ATTR_STA_INFO, head, length, policy, "station message");
        !error.empty())
        return failure(std::move(error));
    if (attributes[NL80211_ATTR_MAC] == nullptr)
        return failure("station message without NL80211_ATTR_MAC");

    StationParseResult result;
    std::memcpy(result.station.mac.data(), nla_data(attributes[NL80211_ATTR_MAC]), sizeof(MacAddress));
    if (attributes[NL80211_ATTR_STA_INFO] != nullptr) {
        if (auto error = parse_station_info(attributes[NL80211_ATTR_STA_INFO], result.station); !error.empty())
            return failure("station " + mac_text(result.station.mac) + ": " + error);
    }
    result.ok = true;
    return result;
}

StationParseResult parse_station_message(nl_msg* message) {
    if (message == nullptr)
        return failure("no station message");
    nlmsghdr* header = nlmsg_hdr(message);
    return parse_station_message(header, header->nlmsg_len);
}

RateReading station_reading(const std::vector<StationInfo>& stations, const std::optional<MacAddress>& peer,
                            const std::string& interface) {
    RateReading reading;
    const StationInfo* chosen = nullptr;
    if (peer) {
        for (const StationInfo& station : stations) {
            if (station.mac == *peer) {
                chosen = &station;
                break;
            }
        }
        if (chosen == nullptr) {
            reading.error = "no station " + mac_text(*peer) + " on " + interface;
            return reading;
        }
    } else if (stations.empty()) {
        reading.error = interface + " has no station: not associated";
        return reading;
    } else if (stations.size() > 1) {
        reading.error = interface + " has " + std::to_string(stations.size()) +
                        " stations; name the peer: nl80211:" + interface + ":PEER_MAC";
        return reading;
    } else {
        chosen = &stations.front();
    }

    std::string detail;
    if (chosen->signal_dbm)
        detail = "signal " + std::to_string(*chosen->signal_dbm) + " dBm, ";
    detail += "station " + mac_text(chosen->mac);
    if (!chosen->tx_bitrate_bps) {
        reading.error = "station " + mac_text(chosen->mac) + " on " + interface + " reports no transmit bit rate";
        reading.detail = std::move(detail);
        return reading;
    }
    reading.ok = true;
    reading.rate_bps = *chosen->tx_bitrate_bps;
    reading.detail = std::move(detail);
    return reading;
}

}  // namespace tgw::sensor
