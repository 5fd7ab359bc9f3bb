#include "gateway/dds/early_heartbeats.hpp"

#include <gtest/gtest.h>

#include <array>

#include "test/unit/wire/rtps_bytes.hpp"

namespace tgw::dds {
namespace {

namespace rtps = test::rtps;

constexpr std::array<std::uint8_t, 4> WRITER{0x00, 0x00, 0x06, 0x03};

TEST(EarlyHeartbeatsTest, LeavesOutTheHeartbeatOfAFragmentThatDoesNotEndItsSample) {
    const rtps::Bytes message = rtps::message({rtps::info_dst(0x22), rtps::info_ts(1), rtps::data_frag(WRITER, 2, 1),
                                               rtps::heartbeat(), rtps::statistics(0)});
    rtps::Bytes out;
    ASSERT_TRUE(without_early_heartbeats(message.data(), message.size(), out));
    EXPECT_EQ(out, rtps::message(
                       {rtps::info_dst(0x22), rtps::info_ts(1), rtps::data_frag(WRITER, 2, 1), rtps::statistics(0)}));
}

TEST(EarlyHeartbeatsTest, KeepsTheHeartbeatOfASamplesLastFragment) {
    // Fragments of 1,024 bytes of a 6,000-byte sample: the sixth ends it.
    const rtps::Bytes message = rtps::message({rtps::data_frag(WRITER, 2, 6), rtps::heartbeat()});
    rtps::Bytes out;
    EXPECT_FALSE(without_early_heartbeats(message.data(), message.size(), out));
    const rtps::Bytes last_two = rtps::message({rtps::data_frag(WRITER, 2, 5, 2), rtps::heartbeat()});
    EXPECT_FALSE(without_early_heartbeats(last_two.data(), last_two.size(), out));
    EXPECT_TRUE(out.empty());
}

TEST(EarlyHeartbeatsTest, LeavesAloneWholeSamplesProtectedMessagesAndMessagesWithoutAHeartbeat) {
    rtps::Bytes out;
    for (const rtps::Bytes& message :
         {rtps::message({rtps::data_of(WRITER, 1), rtps::heartbeat()}), rtps::message({rtps::data_frag(WRITER, 1, 1)}),
          rtps::message(rtps::signed_rtps({rtps::data_frag(WRITER, 1, 1), rtps::heartbeat()}))}) {
        EXPECT_FALSE(without_early_heartbeats(message.data(), message.size(), out));
    }
    EXPECT_TRUE(out.empty());
}

TEST(EarlyHeartbeatsTest, LeavesAloneEveryTruncation) {
    const rtps::Bytes whole = rtps::message({rtps::data_frag(WRITER, 2, 1), rtps::heartbeat()});
    rtps::Bytes out;
    for (std::size_t size = 0; size < whole.size(); ++size) {
        EXPECT_FALSE(without_early_heartbeats(whole.data(), size, out)) << "cut to " << size << " bytes";
    }
}

}  // namespace
}  // namespace tgw::dds
