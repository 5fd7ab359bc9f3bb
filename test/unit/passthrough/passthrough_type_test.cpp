#include "passthrough/passthrough_type.hpp"

#include <gtest/gtest.h>

namespace tgw::passthrough {
namespace {

using namespace std::chrono_literals;

TEST(PassthroughTypeTest, SerializesThePayloadUntouched) {
    PassthroughType sut("any::Type", false);
    PassthroughData in;
    in.payload = {0x00, 0x01, 0x00, 0x00, 1, 2, 3, 4, 5};
    eprosima::fastrtps::rtps::SerializedPayload_t payload(4);
    ASSERT_TRUE(sut.serialize(&in, &payload));
    EXPECT_EQ(payload.length, in.payload.size());
    EXPECT_EQ(payload.encapsulation, CDR_LE);
    PassthroughData out;
    ASSERT_TRUE(sut.deserialize(&payload, &out));
    EXPECT_EQ(out.payload, in.payload);
    EXPECT_STREQ(sut.getName(), "any::Type");
}

TEST(PassthroughTypeTest, KeyIsTheCarriedKeyHashOrTheUnknownInstance) {
    PassthroughType sut("any::Keyed", true);
    PassthroughData data;
    eprosima::fastrtps::rtps::InstanceHandle_t handle;
    ASSERT_TRUE(sut.getKey(&data, &handle));
    EXPECT_EQ(handle, PassthroughType::UNKNOWN_INSTANCE);
    data.key.value[0] = 42;
    ASSERT_TRUE(sut.getKey(&data, &handle));
    EXPECT_EQ(handle, data.key);
    PassthroughType unkeyed("any::Unkeyed", false);
    EXPECT_FALSE(unkeyed.getKey(&data, &handle));
}

}  // namespace
}  // namespace tgw::passthrough
