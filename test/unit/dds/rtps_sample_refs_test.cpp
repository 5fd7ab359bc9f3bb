#include "gateway/dds/rtps_sample_refs.hpp"

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "test/unit/wire/rtps_bytes.hpp"

namespace tgw::dds {
namespace {

namespace rtps = test::rtps;

constexpr std::array<std::uint8_t, 4> WRITER{0x00, 0x00, 0x01, 0x03};
constexpr std::array<std::uint8_t, 4> OTHER_WRITER{0x00, 0x00, 0x02, 0x03};

std::vector<RtpsSampleRef> refs_of(const rtps::Bytes& message) {
    std::array<RtpsSampleRef, 8> out;
    const std::size_t n = rtps_sample_refs(message.data(), message.size(), out.data(), out.size());
    return {out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n)};
}

TEST(RtpsSampleRefsTest, FindsTheWriterAndSequenceOfEachDataAndDataFrag) {
    const std::int64_t high = (std::int64_t{1} << 32) + 9;
    const auto refs = refs_of(rtps::message({rtps::info_ts(1), rtps::data_of(WRITER, 7), rtps::info_ts(2),
                                             rtps::data_frag(OTHER_WRITER, high, 3), rtps::heartbeat()}));
    ASSERT_EQ(refs.size(), 2u);
    EXPECT_EQ(refs[0], (RtpsSampleRef{WRITER, 7, 0}));
    EXPECT_EQ(refs[1], (RtpsSampleRef{OTHER_WRITER, high, 3}));
}

TEST(RtpsSampleRefsTest, ReadsABigEndianSubmessage) {
    rtps::Bytes body(12, 0);
    body.insert(body.end(), {0, 0, 0, 0, 0, 0, 0x01, 0x2c});  // writerSN 300, big endian
    const auto refs = refs_of(rtps::message({rtps::submessage(0x15, 0x04, body)}));
    ASSERT_EQ(refs.size(), 1u);
    EXPECT_EQ(refs[0].sequence, 300);
}

TEST(RtpsSampleRefsTest, FindsNoSampleInAMessageWithoutDataNorInOneProtectedAsAWhole) {
    EXPECT_TRUE(refs_of(rtps::message({rtps::heartbeat()})).empty());
    EXPECT_TRUE(refs_of(rtps::message(rtps::signed_rtps({rtps::data_of(WRITER, 1)}))).empty());
}

TEST(RtpsSampleRefsTest, RefusesEveryTruncationOfAMessage) {
    const rtps::Bytes whole = rtps::message({rtps::info_ts(1), rtps::data_of(WRITER, 7)});
    for (std::size_t size = 0; size < whole.size(); ++size) {
        const rtps::Bytes cut(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(size));
        EXPECT_TRUE(refs_of(cut).empty()) << "cut to " << size << " bytes";
    }
}

TEST(RtpsSampleRefsTest, StopsAtTheCallersMaximum) {
    const auto message = rtps::message({rtps::data_of(WRITER, 1), rtps::data_of(WRITER, 2), rtps::data_of(WRITER, 3)});
    std::array<RtpsSampleRef, 2> out;
    EXPECT_EQ(rtps_sample_refs(message.data(), message.size(), out.data(), out.size()), 2u);
}

}  // namespace
}  // namespace tgw::dds
