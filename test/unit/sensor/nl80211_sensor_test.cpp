#include "sensor/nl80211_sensor.hpp"

#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "base/config_error.hpp"
#include "test/fakes/config_error_of.hpp"
#include "test/fakes/fake_clock.hpp"

namespace tgw::sensor {
namespace {

/// Real queries against interfaces every machine has and none of which is wireless. Whether the kernel has
/// nl80211 at all (a wireless driver loaded) or not, the answer must be the same clean start-up error.
class Nl80211SensorTest : public ::testing::Test {
  protected:
    /// The ConfigError message for `construct`, or "<no error>".
    template <typename F>
    static std::string error_of(F&& construct) {
        return test::config_error_of(std::forward<F>(construct));
    }
};

TEST_F(Nl80211SensorTest, RefusesToStartOnLoopbackAsNotWireless) {
    const std::string error = error_of([] { Nl80211Sensor sut("lo", std::nullopt); });
    EXPECT_EQ(error.rfind("lo is not a wireless interface: ", 0), 0u) << error;
}

TEST_F(Nl80211SensorTest, WaitsForAnInterfaceThatIsNotThereYetNamingItInItsReadings) {
    Nl80211Sensor sut("tgw-nosuch0", std::nullopt);  // a USB radio not plugged in yet
    const RateReading reading = sut.read();
    EXPECT_FALSE(reading.ok);
    EXPECT_EQ(reading.error, "no interface tgw-nosuch0");
}

TEST_F(Nl80211SensorTest, RefusesToStartWithoutAnInterface) {
    EXPECT_EQ(error_of([] { Nl80211Sensor sut("", std::nullopt); }), "no interface given (nl80211:IFACE[:PEER_MAC])");
}

TEST_F(Nl80211SensorTest, FactoryNamesTheSpecAndTheReason) {
    test::FakeClock clock;
    const std::string error = error_of([&] { make_sensor("nl80211:lo:02:00:00:00:01:00", clock); });
    EXPECT_EQ(error.rfind("sensor nl80211:lo:02:00:00:00:01:00: lo is not a wireless interface: ", 0), 0u) << error;
}

TEST_F(Nl80211SensorTest, FactoryRejectsABadPeerMac) {
    test::FakeClock clock;
    EXPECT_EQ(error_of([&] { make_sensor("nl80211:wlan0:02:00:00", clock); }),
              "sensor nl80211:wlan0:02:00:00: '02:00:00' is not a MAC address (for example 02:00:00:00:01:00)");
}

}  // namespace
}  // namespace tgw::sensor
