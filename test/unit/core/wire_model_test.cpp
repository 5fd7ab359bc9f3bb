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
    EXPECT_EQ(sut.wire_bytes(61), 62u + 36u + 64u);
    EXPECT_EQ(sut.wire_bits(64), 8u * (62u + 36u + 64u));
}

TEST_F(WireModelTest, PaperMessageAIsAboutThreeTimesItsData) {
    // 41 bytes of data: 64 serialized with timestamp, sequence and length, 162 on the wire.
    EXPECT_EQ(sut.wire_bytes(paper_message_serialized_bytes(41)), 162u);
}

TEST_F(WireModelTest, LargeSampleFragmentsAndPaysHeadersPerFragment) {
    const std::size_t image = 6'000;
    const std::size_t fragments = (image + sut.fragment_payload_bytes - 1) / sut.fragment_payload_bytes;
    EXPECT_EQ(fragments, 5u);
    EXPECT_EQ(sut.wire_bytes(image), fragments * (62u + 36u) + image);
}

}  // namespace
}  // namespace tgw::core
