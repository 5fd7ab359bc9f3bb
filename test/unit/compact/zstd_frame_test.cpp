#include "compact/zstd_frame.hpp"

#include <gtest/gtest.h>

namespace tgw::compact {
namespace {

/// Counters as a status carries them: mostly zeros and small numbers.
std::vector<std::uint8_t> status_like(std::size_t n) {
    std::vector<std::uint8_t> raw(n, 0);
    for (std::size_t i = 0; i < n; i += 8)
        raw[i] = static_cast<std::uint8_t>(i / 8 % 7);
    return raw;
}

TEST(ZstdFrameTest, RoundTripsAndShrinksWhatRepeats) {
    const std::vector<std::uint8_t> raw = status_like(664);
    std::vector<std::uint8_t> frame;
    ASSERT_TRUE(zstd_frame(raw.data(), raw.size(), frame));
    EXPECT_LT(frame.size(), raw.size() / 3);
    std::vector<std::uint8_t> back;
    ASSERT_EQ(unzstd_frame(frame.data(), frame.size(), raw.size(), back), FrameError::none);
    EXPECT_EQ(back, raw);
}

TEST(ZstdFrameTest, RefusesAFrameThatDeclaresMoreThanItsBoundBeforeDecompressing) {
    const std::vector<std::uint8_t> raw = status_like(100'000);
    std::vector<std::uint8_t> frame;
    ASSERT_TRUE(zstd_frame(raw.data(), raw.size(), frame));
    std::vector<std::uint8_t> back;
    EXPECT_EQ(unzstd_frame(frame.data(), frame.size(), raw.size() - 1, back), FrameError::too_large);
    EXPECT_TRUE(back.empty()) << "nothing decompressed";
}

TEST(ZstdFrameTest, RejectsEveryTruncationTrailingBytesAndGarbage) {
    const std::vector<std::uint8_t> raw = status_like(664);
    std::vector<std::uint8_t> frame;
    ASSERT_TRUE(zstd_frame(raw.data(), raw.size(), frame));
    std::vector<std::uint8_t> back;
    for (std::size_t n = 0; n < frame.size(); ++n) {
        EXPECT_EQ(unzstd_frame(frame.data(), n, 1 << 20, back), FrameError::malformed) << n << " bytes";
    }
    std::vector<std::uint8_t> longer = frame;
    longer.push_back(0);
    EXPECT_EQ(unzstd_frame(longer.data(), longer.size(), 1 << 20, back), FrameError::malformed) << "a byte more";
    const std::vector<std::uint8_t> cdr = {0x00, 0x01, 0x00, 0x00, 1, 2, 3, 4};
    EXPECT_EQ(unzstd_frame(cdr.data(), cdr.size(), 1 << 20, back), FrameError::malformed) << "not a frame";
}

}  // namespace
}  // namespace tgw::compact
