#include "sensor/rate_trace.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "base/config_error.hpp"
#include "test/fakes/config_error_of.hpp"

namespace tgw::sensor {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

class RateTraceTest : public ::testing::Test {
  protected:
    static RateTrace parse(const std::string& text) {
        std::istringstream in(text);
        return parse_rate_trace(in, "link.trace");
    }
    /// The ConfigError message parse() throws, or "<no error>".
    static std::string error_of(const std::string& text) {
        return test::config_error_of([&] { parse(text); });
    }
};

TEST_F(RateTraceTest, ReadsOneStepPerLine) {
    const RateTrace sut = parse("0 20000\n10 5000\n12.5 70000\n");
    ASSERT_EQ(sut.steps().size(), 3u);
    EXPECT_EQ(sut.steps()[0].at, seconds(0));
    EXPECT_EQ(sut.steps()[0].rate_bps, 20'000.0);
    EXPECT_EQ(sut.steps()[2].at, milliseconds(12'500));
    EXPECT_EQ(sut.steps()[2].rate_bps, 70'000.0);
}

TEST_F(RateTraceTest, SkipsCommentsAndBlankLines) {
    const RateTrace sut = parse("# a drive behind the ridge\n\n   \n0 20000   # line of sight\n\t\n5 1000\n#end");
    ASSERT_EQ(sut.steps().size(), 2u);
    EXPECT_EQ(sut.steps()[1].rate_bps, 1'000.0);
}

TEST_F(RateTraceTest, AcceptsCrlfLineEnds) {
    const RateTrace sut = parse("# from Windows\r\n0 20000\r\n\r\n5 1000\r\n");
    ASSERT_EQ(sut.steps().size(), 2u);
    EXPECT_EQ(sut.steps()[1].at, seconds(5));
}

TEST_F(RateTraceTest, AcceptsALastLineWithoutNewline) {
    EXPECT_EQ(parse("0 1\n3 2").steps().size(), 2u);
}

TEST_F(RateTraceTest, AcceptsRateSuffixesAndAZeroRate) {
    const RateTrace sut = parse("0 20k\n1 0\n2 1.5M\n");
    EXPECT_EQ(sut.steps()[0].rate_bps, 20'000.0);
    EXPECT_EQ(sut.steps()[1].rate_bps, 0.0);
    EXPECT_EQ(sut.steps()[2].rate_bps, 1'500'000.0);
}

TEST_F(RateTraceTest, RejectsALineWithAMissingFieldNamingFileAndLine) {
    EXPECT_EQ(error_of("0 20000\n\n5\n"), "link.trace:3: expected `seconds bits_per_second`, got 1 field");
}

TEST_F(RateTraceTest, RejectsALineWithAnExtraField) {
    EXPECT_EQ(error_of("0 20000 7\n"), "link.trace:1: expected `seconds bits_per_second`, got 3 fields");
}

TEST_F(RateTraceTest, RejectsANonNumericTime) {
    EXPECT_EQ(error_of("# header\nzero 20000\n"), "link.trace:2: time 'zero' is not a number of seconds");
}

TEST_F(RateTraceTest, RejectsATimeWithASuffix) {
    EXPECT_EQ(error_of("1k 20000\n"), "link.trace:1: time '1k' is not a number of seconds");
}

TEST_F(RateTraceTest, RejectsANonNumericRate) {
    EXPECT_EQ(error_of("0 fast\n"), "link.trace:1: rate 'fast' is not a number of bit/s");
}

TEST_F(RateTraceTest, RejectsANegativeTime) {
    EXPECT_EQ(error_of("-1 20000\n"), "link.trace:1: time -1 is negative");
}

TEST_F(RateTraceTest, RejectsANegativeRate) {
    EXPECT_EQ(error_of("0 20000\n1 -5\n"), "link.trace:2: rate -5 is negative");
}

TEST_F(RateTraceTest, RejectsARepeatedTime) {
    EXPECT_EQ(error_of("0 20000\n2 100\n2 300\n"), "link.trace:3: time 2 s is not after the previous step's 2 s");
}

TEST_F(RateTraceTest, RejectsATimeGoingBackwards) {
    EXPECT_EQ(error_of("0 20000\n2 100\n1.5 300\n"), "link.trace:3: time 1.5 s is not after the previous step's 2 s");
}

TEST_F(RateTraceTest, RejectsAnAbsurdlyLargeTime) {
    EXPECT_EQ(error_of("1e12 20000\n"), "link.trace:1: time 1e12 is beyond 1000000000 s");
}

TEST_F(RateTraceTest, RejectsAnEmptyFile) {
    EXPECT_EQ(error_of(""), "link.trace: no rate in the trace; expected lines of `seconds bits_per_second`");
}

TEST_F(RateTraceTest, RejectsAFileOfOnlyComments) {
    EXPECT_EQ(error_of("# nothing yet\n\n"),
              "link.trace: no rate in the trace; expected lines of `seconds bits_per_second`");
}

TEST_F(RateTraceTest, RateAtFollowsTheLastStepAtOrBeforeTheTime) {
    const RateTrace sut = parse("0 20000\n10 5000\n20 70000\n");
    EXPECT_EQ(sut.rate_at(seconds(0)), 20'000.0);
    EXPECT_EQ(sut.rate_at(milliseconds(9'999)), 20'000.0);
    EXPECT_EQ(sut.rate_at(seconds(10)), 5'000.0);
    EXPECT_EQ(sut.rate_at(milliseconds(19'999)), 5'000.0);
    EXPECT_EQ(sut.rate_at(seconds(20)), 70'000.0);
}

TEST_F(RateTraceTest, RateAtBeforeTheFirstStepIsTheFirstRate) {
    const RateTrace sut = parse("5 20000\n10 5000\n");
    EXPECT_EQ(sut.rate_at(seconds(0)), 20'000.0);
    EXPECT_EQ(sut.rate_at(seconds(4)), 20'000.0);
}

TEST_F(RateTraceTest, RateAtHoldsTheLastRateForeverAfterTheLastStep) {
    const RateTrace sut = parse("0 20000\n10 5000\n");
    EXPECT_EQ(sut.rate_at(seconds(3600)), 5'000.0);
    EXPECT_EQ(sut.rate_at(base::Duration::max()), 5'000.0);
}

}  // namespace
}  // namespace tgw::sensor
