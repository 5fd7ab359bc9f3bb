// gap_for_repair: the GAP the WAN transport sends instead of a repair of samples past their deadlines.
#include "gateway/dds/gap_for_repair.hpp"

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "test/unit/wire/rtps_bytes.hpp"

namespace tgw::dds {
namespace {

namespace rtps = test::rtps;

constexpr std::array<std::uint8_t, 4> WRITER{0x00, 0x00, 0x07, 0x03};
constexpr std::array<std::uint8_t, 4> OTHER_WRITER{0x00, 0x00, 0x08, 0x03};

rtps::Bytes gap_for(const rtps::Bytes& repair) {
    std::vector<std::uint8_t> out;
    EXPECT_TRUE(gap_for_repair(repair.data(), repair.size(), out));
    return out;
}

TEST(GapForRepairTest, OneGapPerSampleAfterTheHeaderAndTheDestination) {
    const rtps::Bytes repair = rtps::message({rtps::info_dst(0x0b), rtps::info_ts(1), rtps::data_frag(WRITER, 13, 4),
                                              rtps::data_frag(WRITER, 13, 5), rtps::heartbeat()});
    EXPECT_EQ(gap_for(repair), rtps::message({rtps::info_dst(0x0b), rtps::gap(WRITER, 13)}));
}

TEST(GapForRepairTest, EverySampleOfEveryWriterInTheMessage) {
    const rtps::Bytes repair = rtps::message(
        {rtps::info_ts(1), rtps::data_of(WRITER, 7), rtps::data_of(WRITER, 8), rtps::data_frag(OTHER_WRITER, 1, 2)});
    EXPECT_EQ(gap_for(repair), rtps::message({rtps::gap(WRITER, 7), rtps::gap(WRITER, 8), rtps::gap(OTHER_WRITER, 1)}));
}

TEST(GapForRepairTest, KeepsTheSequenceNumbersHighWord) {
    const std::int64_t sequence = (std::int64_t{1} << 32) + 5;
    EXPECT_EQ(gap_for(rtps::message({rtps::data_of(WRITER, sequence)})), rtps::message({rtps::gap(WRITER, sequence)}));
}

TEST(GapForRepairTest, NothingForAMessageWithoutSamplesOrProtectedWhole) {
    std::vector<std::uint8_t> out{0x42};
    const rtps::Bytes heartbeat = rtps::message({rtps::heartbeat()});
    EXPECT_FALSE(gap_for_repair(heartbeat.data(), heartbeat.size(), out));
    const rtps::Bytes secured = rtps::message(rtps::signed_rtps({rtps::data_of(WRITER, 7)}));
    EXPECT_FALSE(gap_for_repair(secured.data(), secured.size(), out));
    EXPECT_EQ(out, (std::vector<std::uint8_t>{0x42})) << "untouched";
}

}  // namespace
}  // namespace tgw::dds
