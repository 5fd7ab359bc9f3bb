#include "sensor/proc_net_wireless.hpp"

#include <gtest/gtest.h>

#include <sstream>

namespace tgw::sensor {
namespace {

constexpr const char* HEADER =
    "Inter-| sta-|   Quality        |   Discarded packets               | Missed | WE\n"
    " face | tus | link level noise |  nwid  crypt   frag  retry   misc | beacon | 22\n";

class ProcNetWirelessTest : public ::testing::Test {
  protected:
    static WirelessTable parse(const std::string& text) {
        std::istringstream in(text);
        return parse_proc_net_wireless(in);
    }
};

TEST_F(ProcNetWirelessTest, ReadsAnInterfaceLineWithUpdateMarks) {
    const WirelessTable sut =
        parse(std::string(HEADER) + " wlan0: 0000   54.  -56.  -256        0      0      0      0      0        0\n");
    ASSERT_TRUE(sut.ok) << sut.error;
    ASSERT_EQ(sut.interfaces.size(), 1u);
    EXPECT_EQ(sut.interfaces[0].interface, "wlan0");
    EXPECT_EQ(sut.interfaces[0].link_quality, 54.0);
    EXPECT_EQ(sut.interfaces[0].level_dbm, -56.0);
    EXPECT_EQ(sut.interfaces[0].noise_dbm, -256.0);
}

TEST_F(ProcNetWirelessTest, ReadsSeveralInterfacesWithAndWithoutMarks) {
    const WirelessTable sut = parse(std::string(HEADER) +
                                    "wlan0: 0000   70  -30  -95  0 0 0 0 0 0\n"
                                    "  wlp3s0: 0000   12.  -88.  -256.  0 0 0 0 0 0\n");
    ASSERT_TRUE(sut.ok) << sut.error;
    ASSERT_EQ(sut.interfaces.size(), 2u);
    EXPECT_EQ(sut.interfaces[0].link_quality, 70.0);
    EXPECT_EQ(sut.interfaces[0].noise_dbm, -95.0);
    EXPECT_EQ(sut.interfaces[1].interface, "wlp3s0");
    EXPECT_EQ(sut.interfaces[1].level_dbm, -88.0);
}

TEST_F(ProcNetWirelessTest, ListsNothingWhenOnlyTheHeaderIsThere) {
    const WirelessTable sut = parse(HEADER);
    ASSERT_TRUE(sut.ok) << sut.error;
    EXPECT_TRUE(sut.interfaces.empty());
    EXPECT_TRUE(parse("").ok);
}

TEST_F(ProcNetWirelessTest, RejectsALineWithTooFewFieldsNamingTheLine) {
    const WirelessTable sut = parse(std::string(HEADER) + "wlan0: 0000 54.\n");
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error, "line 3: expected `wlan0: status link level noise ...`");
    EXPECT_TRUE(sut.interfaces.empty());
}

TEST_F(ProcNetWirelessTest, RejectsQualityThatIsNotNumbers) {
    const WirelessTable sut = parse(std::string(HEADER) + "wlan0: 0000 good -56. -256 0 0 0 0 0 0\n");
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error, "line 3: quality of wlan0 is not numbers: good -56. -256");
}

TEST_F(ProcNetWirelessTest, RejectsALineWithoutAName) {
    const WirelessTable sut = parse(": 0000 54 -56 -256\n");
    EXPECT_FALSE(sut.ok);
    EXPECT_EQ(sut.error, "line 1: no interface name before ':'");
}

}  // namespace
}  // namespace tgw::sensor
