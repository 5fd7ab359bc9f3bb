#include "sensor/wireless_sensor.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "base/config_error.hpp"

namespace tgw::sensor {
namespace {

namespace fs = std::filesystem;

constexpr const char* HEADER =
    "Inter-| sta-|   Quality        |   Discarded packets               | Missed | WE\n"
    " face | tus | link level noise |  nwid  crypt   frag  retry   misc | beacon | 22\n";

/// Each test writes its own stand-in for /proc/net/wireless in a fresh directory.
class WirelessSensorTest : public ::testing::Test {
  protected:
    void SetUp() override {
        std::string pattern = (fs::temp_directory_path() / "tgw-wireless-XXXXXX").string();
        ASSERT_NE(mkdtemp(pattern.data()), nullptr);
        dir = pattern;
        proc = (dir / "wireless").string();
    }
    void TearDown() override {
        std::error_code ignored;
        fs::remove_all(dir, ignored);
    }
    void write_proc(const std::string& lines) const { std::ofstream(proc) << HEADER << lines; }
    std::string error_of(const std::string& interface) const {
        try {
            WirelessSensor sut(interface, LinkQualityTable::default_table(), proc);
        } catch (const base::ConfigError& e) {
            return e.what();
        }
        return "<no error>";
    }

    fs::path dir;
    std::string proc;
    LinkQualityTable table{{{10, 10e3}, {30, 40e3}, {50, 70e3}}};
};

TEST_F(WirelessSensorTest, MapsTheQualityOfItsInterfaceThroughTheTable) {
    write_proc("eth9: 0000 70 -20 -90 0 0 0 0 0 0\nwlan0: 0000   34.  -61.  -256        0 0 0 0 0 0\n");
    WirelessSensor sut("wlan0", table, proc);
    const RateReading reading = sut.read();
    ASSERT_TRUE(reading.ok) << reading.error;
    EXPECT_EQ(reading.rate_bps, 40'000.0);
    EXPECT_EQ(reading.detail, "quality 34, signal -61 dBm");
    EXPECT_EQ(sut.describe(), "wireless:wlan0");
}

TEST_F(WirelessSensorTest, FollowsTheQualityOnEveryRead) {
    write_proc("wlan0: 0000 34. -61. -256 0 0 0 0 0 0\n");
    WirelessSensor sut("wlan0", table, proc);
    write_proc("wlan0: 0000 55. -50. -256 0 0 0 0 0 0\n");
    EXPECT_EQ(sut.read().rate_bps, 70'000.0);
}

TEST_F(WirelessSensorTest, FailsBelowTheTableKeepingTheQualityInTheDetail) {
    write_proc("wlan0: 0000 5. -90. -256 0 0 0 0 0 0\n");
    WirelessSensor sut("wlan0", table, proc);
    const RateReading reading = sut.read();
    EXPECT_FALSE(reading.ok);
    EXPECT_EQ(reading.error, "link quality 5 of wlan0 is below the table's lowest row");
    EXPECT_EQ(reading.detail, "quality 5, signal -90 dBm");
}

TEST_F(WirelessSensorTest, FailsCleanlyWhenTheInterfaceDisappears) {
    write_proc("wlan0: 0000 34. -61. -256 0 0 0 0 0 0\n");
    WirelessSensor sut("wlan0", table, proc);
    write_proc("");
    const RateReading reading = sut.read();
    EXPECT_FALSE(reading.ok);
    EXPECT_EQ(reading.error, proc + " no longer lists wlan0");
    fs::remove(proc);
    EXPECT_EQ(sut.read().error, "cannot read " + proc + ": No such file or directory");
}

TEST_F(WirelessSensorTest, RefusesToStartOnAnUnlistedInterfaceNamingIt) {
    write_proc("wlan0: 0000 34. -61. -256 0 0 0 0 0 0\n");
    EXPECT_EQ(error_of("eth0"), "eth0 is not a wireless interface: " + proc + " does not list it");
}

TEST_F(WirelessSensorTest, RefusesToStartWithoutWirelessExtensions) {
    EXPECT_EQ(error_of("wlan0"), "wlan0 is not a wireless interface: cannot read " + proc +
                                     " (No such file or directory; no wireless extensions in this kernel)");
}

TEST_F(WirelessSensorTest, RefusesToStartOnAnUnreadableTableNamingTheLine) {
    write_proc("wlan0: 0000 34. -61.\n");
    EXPECT_EQ(error_of("wlan0"), proc + ": line 3: expected `wlan0: status link level noise ...`");
}

TEST_F(WirelessSensorTest, FactoryRefusesAnInterfaceTheKernelDoesNotList) {
    // The real /proc/net/wireless: absent here, or without this interface; both name it.
    try {
        WirelessSensor sut("tgw-nosuch0", LinkQualityTable::default_table());
        FAIL() << "expected base::ConfigError";
    } catch (const base::ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("tgw-nosuch0 is not a wireless interface: ", 0), 0u) << e.what();
    }
}

}  // namespace
}  // namespace tgw::sensor
