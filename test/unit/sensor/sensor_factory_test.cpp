#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "base/config_error.hpp"
#include "sensor/guarded_sensor.hpp"
#include "sensor/rate_sensor.hpp"
#include "test/fakes/fake_clock.hpp"

namespace tgw::sensor {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

class SensorFactoryTest : public ::testing::Test {
  protected:
    void SetUp() override {
        std::string pattern = (fs::temp_directory_path() / "tgw-sensor-factory-XXXXXX").string();
        ASSERT_NE(mkdtemp(pattern.data()), nullptr);
        dir = pattern;
    }
    void TearDown() override {
        std::error_code ignored;
        fs::remove_all(dir, ignored);
    }
    std::string write_file(const std::string& name, const std::string& text) {
        const std::string path = (dir / name).string();
        std::ofstream(path) << text;
        return path;
    }
    /// The ConfigError message make_sensor throws for `spec`, or "<no error>".
    std::string error_of(const std::string& spec) {
        try {
            make_sensor(spec, clock);
        } catch (const base::ConfigError& e) {
            return e.what();
        }
        return "<no error>";
    }

    test::FakeClock clock;
    fs::path dir;
};

TEST_F(SensorFactoryTest, MakesAFixedSensorFromAPlainNumber) {
    auto sut = make_sensor("fixed:20000", clock);
    EXPECT_EQ(sut->read().rate_bps, 20'000.0);
    EXPECT_EQ(sut->describe(), "fixed:20000");
}

TEST_F(SensorFactoryTest, MakesAFixedSensorFromSuffixedRates) {
    EXPECT_EQ(make_sensor("fixed:20k", clock)->read().rate_bps, 20'000.0);
    EXPECT_EQ(make_sensor("fixed:1.5M", clock)->read().rate_bps, 1'500'000.0);
}

TEST_F(SensorFactoryTest, RejectsAFixedRateThatIsNotANumber) {
    EXPECT_EQ(error_of("fixed:fast"), "sensor fixed:fast: 'fast' is not a bit rate (for example 20000, 20k, 1.5M)");
    EXPECT_EQ(error_of("fixed:"), "sensor fixed:: '' is not a bit rate (for example 20000, 20k, 1.5M)");
}

TEST_F(SensorFactoryTest, RejectsAFixedRateThatIsNotPositive) {
    EXPECT_EQ(error_of("fixed:0"), "sensor fixed:0: the rate must be above 0 bit/s");
    EXPECT_EQ(error_of("fixed:-20k"), "sensor fixed:-20k: the rate must be above 0 bit/s");
}

TEST_F(SensorFactoryTest, MakesATraceSensorThatFollowsTheInjectedClock) {
    const std::string path = write_file("drive.trace", "0 20000\n10 5000\n");
    auto sut = make_sensor("trace:" + path, clock);
    EXPECT_EQ(sut->read().rate_bps, 20'000.0);
    clock.advance(seconds(10));
    EXPECT_EQ(sut->read().rate_bps, 5'000.0);
    EXPECT_EQ(sut->describe(), "trace:" + path);
}

TEST_F(SensorFactoryTest, RejectsAMissingTraceFileNamingIt) {
    const std::string path = (dir / "missing.trace").string();
    EXPECT_EQ(error_of("trace:" + path),
              "sensor trace:" + path + ": " + path + ": cannot open: No such file or directory");
}

TEST_F(SensorFactoryTest, RejectsABadTraceNamingTheFileAndLine) {
    const std::string path = write_file("bad.trace", "0 20000\n5 lots\n");
    EXPECT_EQ(error_of("trace:" + path),
              "sensor trace:" + path + ": " + path + ":2: rate 'lots' is not a number of bit/s");
}

TEST_F(SensorFactoryTest, RejectsATraceSpecWithoutAFile) {
    EXPECT_EQ(error_of("trace:"), "sensor trace:: no trace file given (trace:FILE)");
}

TEST_F(SensorFactoryTest, RejectsAnNl80211SpecWithoutAnInterface) {
    EXPECT_EQ(error_of("nl80211:"), "sensor nl80211:: no interface given (nl80211:IFACE[:PEER_MAC])");
}

TEST_F(SensorFactoryTest, RejectsAWirelessSpecWithAnUnknownOption) {
    EXPECT_EQ(error_of("wireless:wlan0:rate=5"),
              "sensor wireless:wlan0:rate=5: unknown option 'rate=5', expected wireless:IFACE[:table=FILE]");
    EXPECT_EQ(error_of("wireless:wlan0:table="),
              "sensor wireless:wlan0:table=: unknown option 'table=', expected wireless:IFACE[:table=FILE]");
}

TEST_F(SensorFactoryTest, RejectsABadQualityTableNamingTheFileAndLine) {
    const std::string path = write_file("bad.table", "0 1M\n10 fast\n");
    EXPECT_EQ(error_of("wireless:wlan0:table=" + path),
              "sensor wireless:wlan0:table=" + path + ": " + path + ":2: rate 'fast' is not a number of bit/s");
}

TEST_F(SensorFactoryTest, WrapsASensorInAGuardOnRequest) {
    GuardConfig config;
    config.margin = 0.1;
    auto sut = make_guarded_sensor("fixed:20k", config, clock, nullptr);
    EXPECT_DOUBLE_EQ(sut->read().rate_bps, 18'000.0);
    EXPECT_EQ(sut->describe(), "fixed:20000");
}

TEST_F(SensorFactoryTest, RejectsAnInvalidGuardNamingTheSpecAndField) {
    GuardConfig config;
    config.smoothing = 2.0;
    try {
        make_guarded_sensor("fixed:20k", config, clock, nullptr);
        FAIL() << "expected base::ConfigError";
    } catch (const base::ConfigError& e) {
        EXPECT_EQ(std::string(e.what()), "sensor fixed:20k: smoothing must be in (0, 1]");
    }
}

TEST_F(SensorFactoryTest, RejectsAQdiscSpecWithoutAnInterface) {
    EXPECT_EQ(error_of("qdisc:"), "sensor qdisc:: no interface given (qdisc:IFACE)");
}

TEST_F(SensorFactoryTest, RejectsAnUnknownKindNamingTheSpec) {
    EXPECT_EQ(error_of("iwspy:wlan0"),
              "sensor iwspy:wlan0: unknown kind 'iwspy', expected one of fixed:BPS, trace:FILE, qdisc:IFACE, "
              "nl80211:IFACE[:PEER_MAC], wireless:IFACE[:table=FILE]");
}

TEST_F(SensorFactoryTest, RejectsASpecWithoutAKind) {
    EXPECT_EQ(error_of("20000"),
              "sensor 20000: expected KIND:ARGUMENT, one of fixed:BPS, trace:FILE, qdisc:IFACE, "
              "nl80211:IFACE[:PEER_MAC], wireless:IFACE[:table=FILE]");
    EXPECT_NE(error_of(""), "<no error>");
}

}  // namespace
}  // namespace tgw::sensor
