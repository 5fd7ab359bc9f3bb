#include "sensor/link_quality_table.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "base/config_error.hpp"
#include "test/fakes/config_error_of.hpp"

namespace tgw::sensor {
namespace {

class LinkQualityTableTest : public ::testing::Test {
  protected:
    static LinkQualityTable parse(const std::string& text) {
        std::istringstream in(text);
        return parse_link_quality_table(in, "radio.table");
    }
    /// The ConfigError message parse() throws, or "<no error>".
    static std::string error_of(const std::string& text) {
        return test::config_error_of([&] { parse(text); });
    }
};

TEST_F(LinkQualityTableTest, MapsQualityToTheRateOfItsStep) {
    const LinkQualityTable sut = parse("# a 70 kbit/s radio\n10 10k\n\n30 40k  # fair\n50 70k\n");
    EXPECT_FALSE(sut.rate_for(9.9));
    EXPECT_EQ(sut.rate_for(10), 10'000.0);
    EXPECT_EQ(sut.rate_for(29), 10'000.0);
    EXPECT_EQ(sut.rate_for(30), 40'000.0);
    EXPECT_EQ(sut.rate_for(70), 70'000.0);
}

TEST_F(LinkQualityTableTest, DefaultTableCoversEveryQualityFromZero) {
    const LinkQualityTable sut = LinkQualityTable::default_table();
    EXPECT_EQ(sut.rate_for(0), 500e3);
    EXPECT_EQ(sut.rate_for(54), 18e6);
    EXPECT_EQ(sut.rate_for(70), 25e6);
    EXPECT_FALSE(sut.rate_for(-1));
}

TEST_F(LinkQualityTableTest, RejectsBadRowsNamingTheFileAndLine) {
    EXPECT_EQ(error_of("10 10k\n5 1k\n"), "radio.table:2: quality 5 is not above the previous row's");
    EXPECT_EQ(error_of("10\n"), "radio.table:1: expected `quality bits_per_second`");
    EXPECT_EQ(error_of("10 10k 3\n"), "radio.table:1: expected `quality bits_per_second`");
    EXPECT_EQ(error_of("good 10k\n"), "radio.table:1: quality 'good' is not a number");
    EXPECT_EQ(error_of("10 -1k\n"), "radio.table:1: rate -1k is negative");
    EXPECT_EQ(error_of("10 fast\n"), "radio.table:1: rate 'fast' is not a number of bit/s");
    EXPECT_EQ(error_of("# nothing\n"), "radio.table: no row; expected lines of `quality bits_per_second`");
}

TEST_F(LinkQualityTableTest, RejectsAMissingFileNamingIt) {
    try {
        load_link_quality_table("/nonexistent/radio.table");
        FAIL() << "expected base::ConfigError";
    } catch (const base::ConfigError& e) {
        EXPECT_EQ(std::string(e.what()), "/nonexistent/radio.table: cannot open: No such file or directory");
    }
}

}  // namespace
}  // namespace tgw::sensor
