#include "gateway/core/wire_model.hpp"

#include <gtest/gtest.h>

#include "gateway/core/paper_workload.hpp"

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

}  // namespace
}  // namespace tgw::core
