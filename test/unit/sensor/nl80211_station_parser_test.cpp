#include "sensor/nl80211_station_parser.hpp"

#include <gtest/gtest.h>
#include <linux/nl80211.h>
#include <netlink/attr.h>
#include <netlink/genl/genl.h>
#include <netlink/msg.h>

#include <cstring>
#include <memory>
#include <optional>
#include <vector>

namespace tgw::sensor {
namespace {

constexpr MacAddress AP = {0x02, 0x00, 0x00, 0x00, 0x01, 0x00};
constexpr MacAddress PEER = {0x02, 0x00, 0x00, 0x00, 0x02, 0x00};
/// Any id: a dump reply carries the family id the controller gave nl80211 at run time.
constexpr int FAMILY = 0x1c;

struct MsgFree {
    void operator()(nl_msg* message) const { nlmsg_free(message); }
};
using MsgPtr = std::unique_ptr<nl_msg, MsgFree>;

/// What to put in one station message; unset fields are left out.
struct Station {
    std::optional<MacAddress> mac = AP;
    bool with_sta_info = true;
    std::optional<std::uint32_t> bitrate32;  ///< 100 kbit/s
    std::optional<std::uint16_t> bitrate16;  ///< 100 kbit/s
    std::optional<std::int8_t> signal_dbm;
    std::optional<std::int8_t> signal_avg_dbm;
    std::uint8_t command = NL80211_CMD_NEW_STATION;
};

/// Builds a station message as nl80211_send_station() does, with libnl's own functions.
MsgPtr build(const Station& s) {
    MsgPtr message(nlmsg_alloc());
    EXPECT_NE(genlmsg_put(message.get(), NL_AUTO_PORT, NL_AUTO_SEQ, FAMILY, 0, NLM_F_MULTI, s.command, 0), nullptr);
    EXPECT_EQ(nla_put_u32(message.get(), NL80211_ATTR_IFINDEX, 3), 0);
    if (s.mac) {
        EXPECT_EQ(nla_put(message.get(), NL80211_ATTR_MAC, static_cast<int>(s.mac->size()), s.mac->data()), 0);
    }
    if (s.with_sta_info) {
        nlattr* info = nla_nest_start(message.get(), NL80211_ATTR_STA_INFO);
        EXPECT_EQ(nla_put_u32(message.get(), NL80211_STA_INFO_INACTIVE_TIME, 120), 0);
        if (s.signal_dbm) {
            EXPECT_EQ(nla_put_u8(message.get(), NL80211_STA_INFO_SIGNAL, static_cast<std::uint8_t>(*s.signal_dbm)), 0);
        }
        if (s.signal_avg_dbm) {
            EXPECT_EQ(
                nla_put_u8(message.get(), NL80211_STA_INFO_SIGNAL_AVG, static_cast<std::uint8_t>(*s.signal_avg_dbm)),
                0);
        }
        if (s.bitrate32 || s.bitrate16) {
            nlattr* rate = nla_nest_start(message.get(), NL80211_STA_INFO_TX_BITRATE);
            if (s.bitrate16) {
                EXPECT_EQ(nla_put_u16(message.get(), NL80211_RATE_INFO_BITRATE, *s.bitrate16), 0);
            }
            EXPECT_EQ(nla_put_u8(message.get(), NL80211_RATE_INFO_MCS, 7), 0);
            if (s.bitrate32) {
                EXPECT_EQ(nla_put_u32(message.get(), NL80211_RATE_INFO_BITRATE32, *s.bitrate32), 0);
            }
            nla_nest_end(message.get(), rate);
        }
        nla_nest_end(message.get(), info);
    }
    return message;
}

/// The message's bytes, so that tests can cut or corrupt them.
std::vector<std::uint8_t> bytes_of(nl_msg* message) {
    const nlmsghdr* header = nlmsg_hdr(message);
    const auto* begin = reinterpret_cast<const std::uint8_t*>(header);
    return {begin, begin + header->nlmsg_len};
}

void set_length(std::vector<std::uint8_t>& bytes, std::uint32_t length) {
    std::memcpy(bytes.data() + offsetof(nlmsghdr, nlmsg_len), &length, sizeof length);
}

class Nl80211StationParserTest : public ::testing::Test {};

TEST_F(Nl80211StationParserTest, ReadsTheThirtyTwoBitRateAndTheSignal) {
    Station station;
    station.bitrate32 = 540;  // 54 Mbit/s
    station.bitrate16 = 540;
    station.signal_dbm = -52;
    const MsgPtr message = build(station);
    const StationParseResult sut = parse_station_message(message.get());
    ASSERT_TRUE(sut.ok) << sut.error;
    EXPECT_EQ(sut.station.mac, AP);
    EXPECT_EQ(sut.station.tx_bitrate_bps, 54'000'000.0);
    EXPECT_EQ(sut.station.signal_dbm, -52);
}

TEST_F(Nl80211StationParserTest, PrefersTheThirtyTwoBitRateBeyondWhatSixteenBitsHold) {
    Station station;
    station.bitrate32 = 96'080;  // 9.608 Gbit/s, which the kernel cannot put in BITRATE
    station.bitrate16 = 1;
    const MsgPtr message = build(station);
    const StationParseResult sut = parse_station_message(message.get());
    ASSERT_TRUE(sut.ok) << sut.error;
    EXPECT_EQ(sut.station.tx_bitrate_bps, 9'608'000'000.0);
}

TEST_F(Nl80211StationParserTest, FallsBackToTheSixteenBitRate) {
    Station station;
    station.bitrate16 = 10;  // 1 Mbit/s, an old kernel
    const MsgPtr message = build(station);
    const StationParseResult sut = parse_station_message(message.get());
    ASSERT_TRUE(sut.ok) << sut.error;
    EXPECT_EQ(sut.station.tx_bitrate_bps, 1'000'000.0);
    EXPECT_FALSE(sut.station.signal_dbm);
}

TEST_F(Nl80211StationParserTest, TakesTheAverageSignalWhenTheLastIsMissing) {
    Station station;
    station.signal_avg_dbm = -71;
    const MsgPtr message = build(station);
    const StationParseResult sut = parse_station_message(message.get());
    ASSERT_TRUE(sut.ok) << sut.error;
    EXPECT_EQ(sut.station.signal_dbm, -71);
}

TEST_F(Nl80211StationParserTest, LeavesTheRateUnknownWithoutTxBitrate) {
    Station station;
    station.signal_dbm = -60;
    const MsgPtr message = build(station);
    const StationParseResult sut = parse_station_message(message.get());
    ASSERT_TRUE(sut.ok) << sut.error;
    EXPECT_FALSE(sut.station.tx_bitrate_bps);
}

TEST_F(Nl80211StationParserTest, LeavesTheRateUnknownWhenTheDriverReportsZero) {
    Station station;
    station.bitrate32 = 0;
    const MsgPtr message = build(station);
    const StationParseResult sut = parse_station_message(message.get());
    ASSERT_TRUE(sut.ok) << sut.error;
    EXPECT_FALSE(sut.station.tx_bitrate_bps);
}

TEST_F(Nl80211StationParserTest, AcceptsAStationWithoutStaInfo) {
    Station station;
    station.with_sta_info = false;
    const MsgPtr message = build(station);
    const StationParseResult sut = parse_station_message(message.get());
    ASSERT_TRUE(sut.ok) << sut.error;
    EXPECT_FALSE(sut.station.tx_bitrate_bps);
    EXPECT_FALSE(sut.station.signal_dbm);
}

TEST_F(Nl80211StationParserTest, RejectsAStationWithoutAMac) {
    Station station;
    station.mac.reset();
    const MsgPtr message = build(station);
    const StationParseResult sut = parse_station_message(message.get());
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error, "station message without NL80211_ATTR_MAC");
}

TEST_F(Nl80211StationParserTest, RejectsAMacOfTheWrongLength) {
    MsgPtr message(nlmsg_alloc());
    genlmsg_put(message.get(), NL_AUTO_PORT, NL_AUTO_SEQ, FAMILY, 0, 0, NL80211_CMD_NEW_STATION, 0);
    const std::uint8_t short_mac[4] = {1, 2, 3, 4};
    nla_put(message.get(), NL80211_ATTR_MAC, sizeof short_mac, short_mac);
    const StationParseResult sut = parse_station_message(message.get());
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error.rfind("malformed station message: ", 0), 0u) << sut.error;
}

TEST_F(Nl80211StationParserTest, RejectsARateOfTheWrongLength) {
    MsgPtr message(nlmsg_alloc());
    genlmsg_put(message.get(), NL_AUTO_PORT, NL_AUTO_SEQ, FAMILY, 0, 0, NL80211_CMD_NEW_STATION, 0);
    nla_put(message.get(), NL80211_ATTR_MAC, static_cast<int>(AP.size()), AP.data());
    nlattr* info = nla_nest_start(message.get(), NL80211_ATTR_STA_INFO);
    nlattr* rate = nla_nest_start(message.get(), NL80211_STA_INFO_TX_BITRATE);
    nla_put_u8(message.get(), NL80211_RATE_INFO_BITRATE32, 5);  // a u32 attribute with one byte
    nla_nest_end(message.get(), rate);
    nla_nest_end(message.get(), info);
    const StationParseResult sut = parse_station_message(message.get());
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error.rfind("station 02:00:00:00:01:00: malformed NL80211_STA_INFO_TX_BITRATE", 0), 0u) << sut.error;
}

TEST_F(Nl80211StationParserTest, RejectsAMessageOfAnotherCommand) {
    Station station;
    station.command = NL80211_CMD_NEW_INTERFACE;
    const MsgPtr message = build(station);
    const StationParseResult sut = parse_station_message(message.get());
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error, "not a station message: nl80211 command " + std::to_string(NL80211_CMD_NEW_INTERFACE));
}

TEST_F(Nl80211StationParserTest, RejectsAMessageCutInsideItsLastAttribute) {
    Station station;
    station.bitrate32 = 540;
    station.signal_dbm = -40;
    const MsgPtr message = build(station);
    std::vector<std::uint8_t> bytes = bytes_of(message.get());
    // Cut the outer STA_INFO nest short, as a reader that stopped early would: the header agrees with the bytes.
    bytes.resize(bytes.size() - 6);
    set_length(bytes, static_cast<std::uint32_t>(bytes.size()));
    const StationParseResult sut = parse_station_message(bytes.data(), bytes.size());
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error.rfind("truncated station message: ", 0), 0u) << sut.error;
}

TEST_F(Nl80211StationParserTest, RejectsAMessageShorterThanItsHeaderSays) {
    Station station;
    station.bitrate32 = 540;
    const MsgPtr message = build(station);
    std::vector<std::uint8_t> bytes = bytes_of(message.get());
    const std::size_t full = bytes.size();
    bytes.resize(full - 8);
    const StationParseResult sut = parse_station_message(bytes.data(), bytes.size());
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error, "truncated station message: its header says " + std::to_string(full) + " bytes, " +
                             std::to_string(full - 8) + " arrived");
}

TEST_F(Nl80211StationParserTest, RejectsMessagesTooShortForTheHeaders) {
    const std::vector<std::uint8_t> tiny(8, 0);
    EXPECT_EQ(parse_station_message(tiny.data(), tiny.size()).error,
              "truncated station message: 8 bytes, less than a netlink header");
    EXPECT_FALSE(parse_station_message(nullptr, 0).ok);

    std::vector<std::uint8_t> no_genl(NLMSG_HDRLEN + 2, 0);
    set_length(no_genl, static_cast<std::uint32_t>(no_genl.size()));
    EXPECT_EQ(parse_station_message(no_genl.data(), no_genl.size()).error,
              "truncated station message: no generic netlink header");
}

TEST_F(Nl80211StationParserTest, RejectsANestWhoseLengthRunsPastTheMessage) {
    Station station;
    station.bitrate32 = 540;
    const MsgPtr message = build(station);
    std::vector<std::uint8_t> bytes = bytes_of(message.get());
    // Find STA_INFO's header and claim it is longer than what follows.
    const std::size_t attributes = NLMSG_HDRLEN + GENL_HDRLEN;
    std::size_t at = attributes;
    while (at + sizeof(nlattr) <= bytes.size()) {
        nlattr header{};
        std::memcpy(&header, bytes.data() + at, sizeof header);
        if ((header.nla_type & NLA_TYPE_MASK) == NL80211_ATTR_STA_INFO) {
            header.nla_len = static_cast<std::uint16_t>(header.nla_len + 64);
            std::memcpy(bytes.data() + at, &header, sizeof header);
            break;
        }
        at += NLA_ALIGN(header.nla_len);
    }
    ASSERT_LT(at + sizeof(nlattr), bytes.size());
    const StationParseResult sut = parse_station_message(bytes.data(), bytes.size());
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error.rfind("truncated station message: ", 0), 0u) << sut.error;
}

TEST_F(Nl80211StationParserTest, SurvivesEveryPrefixOfAValidMessage) {
    Station station;
    station.bitrate32 = 540;
    station.signal_dbm = -40;
    const MsgPtr message = build(station);
    const std::vector<std::uint8_t> whole = bytes_of(message.get());
    for (std::size_t size = 0; size < whole.size(); ++size) {
        std::vector<std::uint8_t> prefix(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(size));
        EXPECT_FALSE(parse_station_message(prefix.data(), prefix.size()).ok) << size;  // header still says `whole`
        if (size >= NLMSG_HDRLEN) {
            set_length(prefix, static_cast<std::uint32_t>(size));
            (void)parse_station_message(prefix.data(), prefix.size());  // must not crash; may parse
        }
    }
}

class StationReadingTest : public ::testing::Test {
  protected:
    static StationInfo station(MacAddress mac, std::optional<double> rate_bps, std::optional<int> signal_dbm) {
        StationInfo info;
        info.mac = mac;
        info.tx_bitrate_bps = rate_bps;
        info.signal_dbm = signal_dbm;
        return info;
    }
};

TEST_F(StationReadingTest, TakesTheOnlyStationWithoutAPeer) {
    const RateReading sut = station_reading({station(AP, 54e6, -52)}, std::nullopt, "wlan0");
    ASSERT_TRUE(sut.ok) << sut.error;
    EXPECT_EQ(sut.rate_bps, 54e6);
    EXPECT_EQ(sut.detail, "signal -52 dBm, station 02:00:00:00:01:00");
}

TEST_F(StationReadingTest, PicksThePeerAmongSeveralStations) {
    const std::vector<StationInfo> stations = {station(AP, 54e6, -52), station(PEER, 6.5e6, -80)};
    const RateReading sut = station_reading(stations, PEER, "wlan0");
    ASSERT_TRUE(sut.ok) << sut.error;
    EXPECT_EQ(sut.rate_bps, 6.5e6);
    EXPECT_EQ(sut.detail, "signal -80 dBm, station 02:00:00:00:02:00");
}

TEST_F(StationReadingTest, PicksThePeerFromParsedDumpMessages) {
    Station first;
    first.bitrate32 = 540;
    first.signal_dbm = -52;
    Station second;
    second.mac = PEER;
    second.bitrate16 = 65;
    second.signal_dbm = -80;
    std::vector<StationInfo> stations;
    for (const Station& s : {first, second}) {
        const MsgPtr message = build(s);
        const StationParseResult parsed = parse_station_message(message.get());
        ASSERT_TRUE(parsed.ok) << parsed.error;
        stations.push_back(parsed.station);
    }
    EXPECT_EQ(station_reading(stations, PEER, "mesh0").rate_bps, 6.5e6);
    EXPECT_EQ(station_reading(stations, AP, "mesh0").rate_bps, 54e6);
}

TEST_F(StationReadingTest, AsksForAPeerWhenSeveralStationsAreThere) {
    const RateReading sut = station_reading({station(AP, 54e6, -52), station(PEER, 6.5e6, -80)}, std::nullopt, "wlan0");
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error, "wlan0 has 2 stations; name the peer: nl80211:wlan0:PEER_MAC");
}

TEST_F(StationReadingTest, FailsWhenThePeerIsNotThere) {
    const RateReading sut = station_reading({station(AP, 54e6, -52)}, PEER, "wlan0");
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error, "no station 02:00:00:00:02:00 on wlan0");
}

TEST_F(StationReadingTest, FailsWhenNotAssociated) {
    const RateReading sut = station_reading({}, std::nullopt, "wlan0");
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error, "wlan0 has no station: not associated");
}

TEST_F(StationReadingTest, FailsWhenTheStationHasNoRateButKeepsTheSignal) {
    const RateReading sut = station_reading({station(AP, std::nullopt, -90)}, std::nullopt, "wlan0");
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error, "station 02:00:00:00:01:00 on wlan0 reports no transmit bit rate");
    EXPECT_EQ(sut.detail, "signal -90 dBm, station 02:00:00:00:01:00");
}

TEST_F(StationReadingTest, LeavesTheSignalOutWhenUnknown) {
    const RateReading sut = station_reading({station(AP, 1e6, std::nullopt)}, std::nullopt, "wlan0");
    EXPECT_EQ(sut.detail, "station 02:00:00:00:01:00");
}

TEST(MacAddressTest, ParsesBothSeparatorsAndCases) {
    EXPECT_EQ(parse_mac("02:00:00:00:01:00"), AP);
    EXPECT_EQ(parse_mac("02-00-00-00-01-00"), AP);
    EXPECT_EQ(parse_mac("AA:bb:Cc:00:01:ff"), (MacAddress{0xaa, 0xbb, 0xcc, 0x00, 0x01, 0xff}));
    EXPECT_EQ(mac_text({0xaa, 0xbb, 0xcc, 0x00, 0x01, 0xff}), "aa:bb:cc:00:01:ff");
}

TEST(MacAddressTest, RejectsAnythingElse) {
    EXPECT_FALSE(parse_mac(""));
    EXPECT_FALSE(parse_mac("02:00:00:00:01"));
    EXPECT_FALSE(parse_mac("02:00:00:00:01:0g"));
    EXPECT_FALSE(parse_mac("02:00-00:00:01:00"));
    EXPECT_FALSE(parse_mac("02:00:00:00:01:00:"));
    EXPECT_FALSE(parse_mac("0200.0000.0100.00"));
}

}  // namespace
}  // namespace tgw::sensor
