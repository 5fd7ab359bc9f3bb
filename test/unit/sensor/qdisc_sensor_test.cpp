#include "sensor/qdisc_sensor.hpp"

#include <gtest/gtest.h>

#include <string>

#include "base/config_error.hpp"
#include "test/fakes/fake_clock.hpp"
#include "test/fakes/test_netns.hpp"

namespace tgw::sensor {
namespace {

/// Each test builds its own network namespace with a veth pair (tgwa, tgwb), a tbf at the root of tgwa, and
/// enters it on the test's thread so that the sensor's netlink socket sees it (test::TestNetns: named after the
/// process and the test, removed even when the test fails).
class QdiscSensorTest : public ::testing::Test {
  protected:
    void SetUp() override {
        ASSERT_NO_FATAL_FAILURE(netns_.enter(
            "qdisc", {"ip link add tgwa type veth peer name tgwb", "ip link set tgwa up", "ip link set tgwb up",
                      "tc qdisc add dev tgwa root tbf rate 20kbit burst 1600 latency 100ms"}));
    }

    bool in_netns(const std::string& command) const { return netns_.run(command); }

    test::TestNetns netns_;
};

TEST_F(QdiscSensorTest, ReadsTheRateOfTheRootTbf) {
    QdiscSensor sut("tgwa");
    const RateReading reading = sut.read();
    ASSERT_TRUE(reading.ok) << reading.error;
    EXPECT_EQ(reading.rate_bps, 20'000.0);
    EXPECT_EQ(reading.detail, "tbf, backlog 0 B");
    EXPECT_EQ(reading.queued_bytes, std::optional<std::uint64_t>(0));
    EXPECT_EQ(sut.describe(), "qdisc:tgwa");
}

TEST_F(QdiscSensorTest, FollowsTcQdiscChangeOnTheNextRead) {
    QdiscSensor sut("tgwa");
    ASSERT_TRUE(in_netns("tc qdisc change dev tgwa root tbf rate 56kbit burst 1600 latency 100ms"));
    const RateReading reading = sut.read();
    ASSERT_TRUE(reading.ok) << reading.error;
    EXPECT_EQ(reading.rate_bps, 56'000.0);
}

TEST_F(QdiscSensorTest, ReadsTheRateOfTheTopLevelHtbClass) {
    ASSERT_TRUE(in_netns("tc qdisc add dev tgwb root handle 1: htb default 1"));
    ASSERT_TRUE(in_netns("tc class add dev tgwb parent 1: classid 1:1 htb rate 30kbit"));
    QdiscSensor sut("tgwb");
    const RateReading reading = sut.read();
    ASSERT_TRUE(reading.ok) << reading.error;
    EXPECT_EQ(reading.rate_bps, 30'000.0);
    EXPECT_EQ(reading.detail, "htb class 1:1, backlog 0 B");
}

TEST_F(QdiscSensorTest, ReadingFailsCleanlyOnceTheQdiscIsRemoved) {
    QdiscSensor sut("tgwa");
    ASSERT_TRUE(in_netns("tc qdisc del dev tgwa root"));
    const RateReading reading = sut.read();
    EXPECT_FALSE(reading.ok);
    EXPECT_NE(reading.error.find("tgwa"), std::string::npos) << reading.error;
}

TEST_F(QdiscSensorTest, ReadingFailsCleanlyOnceTheInterfaceIsGone) {
    QdiscSensor sut("tgwa");
    ASSERT_TRUE(in_netns("ip link del tgwa"));
    const RateReading reading = sut.read();
    EXPECT_FALSE(reading.ok);
    EXPECT_NE(reading.error.find("no interface tgwa"), std::string::npos) << reading.error;
}

TEST_F(QdiscSensorTest, WaitsForAnInterfaceThatIsNotThereYet) {
    QdiscSensor sut("tgwc");  // a radio that comes up after the gateway started
    const RateReading before = sut.read();
    EXPECT_FALSE(before.ok);
    EXPECT_NE(before.error.find("no interface tgwc"), std::string::npos) << before.error;
    ASSERT_TRUE(in_netns("ip link add tgwc type veth peer name tgwd"));
    ASSERT_TRUE(in_netns("tc qdisc add dev tgwc root tbf rate 32kbit burst 1600 latency 100ms"));
    const RateReading after = sut.read();
    ASSERT_TRUE(after.ok) << after.error;
    EXPECT_EQ(after.rate_bps, 32'000.0);
}

TEST_F(QdiscSensorTest, RefusesToStartOnAnInterfaceWithoutAShaper) {
    try {
        QdiscSensor sut("tgwb");
        FAIL() << "expected base::ConfigError";
    } catch (const base::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("tgwb"), std::string::npos) << e.what();
    }
}

TEST_F(QdiscSensorTest, IsWhatTheFactoryMakesForAQdiscSpec) {
    test::FakeClock clock;
    auto sut = make_sensor("qdisc:tgwa", clock);
    EXPECT_EQ(sut->describe(), "qdisc:tgwa");
    EXPECT_EQ(sut->read().rate_bps, 20'000.0);
    try {
        make_sensor("qdisc:tgwb", clock);
        FAIL() << "expected base::ConfigError";
    } catch (const base::ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("sensor qdisc:tgwb: ", 0), 0u) << e.what();
    }
}

}  // namespace
}  // namespace tgw::sensor
