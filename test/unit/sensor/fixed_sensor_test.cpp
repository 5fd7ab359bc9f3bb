#include "sensor/fixed_sensor.hpp"

#include <gtest/gtest.h>

namespace tgw::sensor {
namespace {

class FixedSensorTest : public ::testing::Test {
  protected:
    FixedSensor sut{20'000.0};
};

TEST_F(FixedSensorTest, EveryReadingSucceedsWithTheConfiguredRate) {
    for (int i = 0; i < 3; ++i) {
        const RateReading reading = sut.read();
        EXPECT_TRUE(reading.ok);
        EXPECT_EQ(reading.rate_bps, 20'000.0);
        EXPECT_TRUE(reading.error.empty());
    }
}

TEST_F(FixedSensorTest, DescribesItselfAsASpec) {
    EXPECT_EQ(sut.describe(), "fixed:20000");
}

}  // namespace
}  // namespace tgw::sensor
