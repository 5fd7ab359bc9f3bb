#include "core/wire_model.hpp"

#include <gtest/gtest.h>

#include "core/bundle_builder.hpp"
#include "core/paper_workload.hpp"

namespace tgw::core {
namespace {

class WireModelTest : public ::testing::Test {
  protected:
    WireModel sut;
};

TEST_F(WireModelTest, SmallSampleCostsDatagramAndSampleHeadersPlusPaddedPayload) {
    EXPECT_EQ(sut.wire_bytes(61), 138u + 36u + 64u);
    EXPECT_EQ(sut.wire_bits(64), 8u * (138u + 36u + 64u));
}

// Frame sizes as tcpdump saw them on the testbed's veth (UDP length + 42).
TEST_F(WireModelTest, PaperMessagesCostWhatTheCaptureShowed) {
    EXPECT_EQ(sut.wire_bytes(paper_message_serialized_bytes(41)), 238u);
    EXPECT_EQ(sut.wire_bytes(paper_message_serialized_bytes(66)), 262u);
    EXPECT_EQ(sut.wire_bytes(paper_message_serialized_bytes(266)), 462u);
    EXPECT_EQ(sut.wire_bytes(paper_message_serialized_bytes(1016)), 1210u);
}

TEST_F(WireModelTest, LargeSampleFragmentsAndPaysHeadersPerFragment) {
    // 3,020 serialized bytes went as frames of 1482, 1482 and 614 bytes; 6,020 as four of 1482 and one of 1022.
    EXPECT_EQ(sut.wire_bytes(3'020), 1482u + 1482u + 614u);
    EXPECT_EQ(sut.wire_bytes(6'020), 4 * 1482u + 1022u);
}

TEST_F(WireModelTest, TheFirstDatagramOfAFragmentedSampleIsOneFullFragment) {
    EXPECT_EQ(sut.first_datagram_wire_bytes(6'020), 1482u);
    EXPECT_EQ(sut.first_datagram_wire_bytes(paper_message_serialized_bytes(1016)), 1210u) << "not fragmented: whole";
}

TEST(WireModelForMaxDatagram, AtOneFrameIsTheCapturedModel) {
    const WireModel captured;
    const WireModel derived = WireModel::for_max_datagram(WireModel::MAX_DATAGRAM_PAYLOAD_BYTES);
    for (std::size_t payload : {0u, 61u, 1'308u, 1'309u, 3'020u, 6'020u, 65'536u}) {
        EXPECT_EQ(derived.wire_bytes(payload), captured.wire_bytes(payload)) << payload << " bytes";
    }
}

TEST(WireModelForMaxDatagram, LargeDatagramPaysIpFragmentHeadersInsteadOfRtpsFragments) {
    const WireModel sut = WireModel::for_max_datagram(WireModel::MAX_UDP_PAYLOAD_BYTES);
    // 3,020 bytes in one DATA: 138 + 36 + 3,020 = 3,194 bytes, 3,160 of IP payload, so 3 frames: 2 more
    // Ethernet and IP headers of 34 bytes.
    EXPECT_EQ(sut.wire_bytes(3'020), 3'194u + 2 * 34u);
    // A sample that fits one frame costs what it always did.
    EXPECT_EQ(sut.wire_bytes(paper_message_serialized_bytes(1016)), 1210u);
    // 64 KiB: two DATA_FRAGs (65,324 + 212 bytes) instead of 51.
    EXPECT_LT(sut.wire_bytes(65'536), WireModel{}.wire_bytes(65'536));
    EXPECT_EQ(sut.max_unfragmented_bytes, 65'336u);
}

TEST(WireModelWithSecurity, PaperMessagesCostWhatTheLoopbackCaptureShowed) {
    // Frames on loopback (UDP length + 42) with scripts/make-certs' governance, --wan-max-datagram 8192.
    const WireModel sut = WireModel::for_max_datagram(8192).with_security();
    EXPECT_EQ(sut.wire_bytes(paper_message_serialized_bytes(41)), 466u);
    EXPECT_EQ(sut.wire_bytes(paper_message_serialized_bytes(66)), 490u);
    EXPECT_EQ(sut.wire_bytes(paper_message_serialized_bytes(266)), 690u);
    EXPECT_EQ(sut.wire_bytes(paper_message_serialized_bytes(1016)), 1438u);
}

TEST(WireModelWithSecurity, CostsEachMessageAndEachSampleTheirProtection) {
    const WireModel plain = WireModel::for_max_datagram(8192);
    const WireModel sut = plain.with_security();
    EXPECT_EQ(sut.wire_bytes(64) - plain.wire_bytes(64), 72u + 2 * 56u + 44u);
    // A fragmented sample pays the payload's protection once and each fragment's message and headers: 3 full
    // DATA_FRAGs of 8,192 - 176 - 228 = 7,788 bytes, each in a datagram of 210 + 48 + 112 + 7,788 = 8,158 bytes, six
    // IP fragments (five more Ethernet and IP headers of 34 bytes).
    EXPECT_EQ(sut.fragment_payload_bytes, 7'788u);
    EXPECT_EQ(sut.wire_bytes(3 * 7'788 - 44), 3 * (8'158u + 5 * 34u));
    EXPECT_EQ(sut.max_unfragmented_bytes, plain.max_unfragmented_bytes - 228u);
}

TEST(WireModelWithSecurity, KeepsCompactBundlesClearOfFastDdsFillLimit) {
    const WireModel plain = WireModel::for_max_datagram(8192);
    const WireModel sut = plain.with_security();
    // The payload's protection and the margin Fast DDS 2.9 needs for the message's: 7,800 - 44 - 256 - 8 - 16.
    EXPECT_EQ(BundleLimits::one_datagram(sut), 7'476u);
    EXPECT_EQ(BundleLimits::one_datagram(plain), plain.max_unfragmented_bytes - 24u);
}

TEST(WireModelWithSecurity, LeavesOutTheStatisticsSubmessageAsThePlainModelDoes) {
    const WireModel sut = WireModel::for_max_datagram(8192).with_security().without_statistics();
    EXPECT_EQ(sut.wire_bytes(paper_message_serialized_bytes(41)), 466u - WireModel::STATISTICS_SUBMESSAGE_BYTES);
}

}  // namespace
}  // namespace tgw::core
