// read_send_stamp: the send time and sequence a Fast DDS transport wrote into a datagram's statistics submessage.
#include "wire/send_stamp.hpp"

#include <gtest/gtest.h>

#include <cstdint>

#include "test/unit/wire/rtps_bytes.hpp"

namespace tgw::wire {
namespace {

using test::rtps::Bytes;
using test::rtps::data;
using test::rtps::info_ts;
using test::rtps::message;
using test::rtps::statistics;

/// A sample's message from participant 0x05, stamped as its transport sent it: `seconds` and a half, the 17th
/// datagram to its destination 10.77.0.6:7411.
Bytes stamped(std::uint32_t seconds) {
    Bytes m = message({info_ts(1), data(40), statistics(0)}, 0x05);
    test::rtps::stamp(m, seconds, 17);
    return m;
}

TEST(SendStampTest, ReadsTheSenderTheTimeAndTheSequence) {
    const Bytes m = stamped(1'795'795'450);
    const auto stamp = read_send_stamp(m.data(), m.size());
    ASSERT_TRUE(stamp.has_value());
    EXPECT_EQ(stamp->sender, (std::array<std::uint8_t, 12>{5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5}));
    EXPECT_EQ(base::to_ns(stamp->sent), 1'795'795'450'500'000'000);
    EXPECT_EQ(stamp->sequence, 17u);
    EXPECT_EQ(stamp->destination[0], 1);
    EXPECT_EQ(stamp->destination[23], 6);
}

TEST(SendStampTest, NoStampWhereNoneWasWritten) {
    const Bytes bare = message({info_ts(1), data(40)}, 0x05);
    EXPECT_FALSE(read_send_stamp(bare.data(), bare.size())) << "no statistics submessage (a compact-mode gateway)";
    const Bytes unfilled = message({info_ts(1), data(40), statistics(0)}, 0x05);
    EXPECT_FALSE(read_send_stamp(unfilled.data(), unfilled.size())) << "never stamped";
    const Bytes m = stamped(1'795'795'450);
    EXPECT_FALSE(read_send_stamp(m.data(), m.size() - 1)) << "truncated";
    EXPECT_FALSE(read_send_stamp(m.data(), 10)) << "shorter than a header";
    Bytes other = m;
    other[0] = 'X';
    EXPECT_FALSE(read_send_stamp(other.data(), other.size())) << "not RTPS";
    EXPECT_FALSE(read_send_stamp(nullptr, 0));
}

}  // namespace
}  // namespace tgw::wire
