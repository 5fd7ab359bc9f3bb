#include "sensor/bit_rate.hpp"

#include <gtest/gtest.h>

namespace tgw::sensor {
namespace {

class BitRateTest : public ::testing::Test {};

TEST_F(BitRateTest, ParsesPlainNumbers) {
    EXPECT_EQ(parse_bit_rate("20000"), 20000.0);
    EXPECT_EQ(parse_bit_rate("1.5e4"), 15000.0);
    EXPECT_EQ(parse_bit_rate("+300"), 300.0);
    EXPECT_EQ(parse_bit_rate("0"), 0.0);
}

TEST_F(BitRateTest, ParsesDecimalSuffixes) {
    EXPECT_EQ(parse_bit_rate("20k"), 20'000.0);
    EXPECT_EQ(parse_bit_rate("20K"), 20'000.0);
    EXPECT_EQ(parse_bit_rate("1.5M"), 1'500'000.0);
    EXPECT_EQ(parse_bit_rate("2G"), 2e9);
}

TEST_F(BitRateTest, LeavesTheSignToTheCaller) {
    EXPECT_EQ(parse_bit_rate("-5k"), -5'000.0);
}

TEST_F(BitRateTest, RejectsAnythingElse) {
    for (const char* text : {"", "k", "abc", "20kb", "20 k", " 20", "20m", "1,5M", "nan", "inf", "1e999", "0x10"})
        EXPECT_FALSE(parse_bit_rate(text).has_value()) << "'" << text << "'";
}

}  // namespace
}  // namespace tgw::sensor
