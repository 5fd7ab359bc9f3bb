// Which lane of a topic forwards each robot writer's samples: every sample crosses once.
#include "passthrough/lane_assignment.hpp"

#include <gtest/gtest.h>

namespace tgw::passthrough {
namespace {

using eprosima::fastrtps::rtps::GUID_t;
using eprosima::fastrtps::rtps::InstanceHandle_t;

GUID_t writer_guid(std::uint8_t n) {
    GUID_t guid;
    guid.guidPrefix.value[0] = n;
    guid.entityId.value[3] = 0x03;
    return guid;
}

TEST(LaneAssignmentTest, WithOneLaneEveryWriterTakesIt) {
    LaneAssignment lanes;
    lanes.assign(writer_guid(1), 0);
    EXPECT_TRUE(lanes.carries(InstanceHandle_t(writer_guid(1)), 0));
    EXPECT_TRUE(lanes.carries(InstanceHandle_t(writer_guid(2)), 0)) << "a writer not assigned yet";
}

TEST(LaneAssignmentTest, AWriterOnALaneOfItsOwnCrossesThroughItAlone) {
    LaneAssignment lanes;
    lanes.assign(writer_guid(1), 0);
    lanes.assign(writer_guid(2), 1);  // a reliable writer meets lane 0's best-effort reader too
    EXPECT_TRUE(lanes.carries(InstanceHandle_t(writer_guid(2)), 1));
    EXPECT_FALSE(lanes.carries(InstanceHandle_t(writer_guid(2)), 0));
    EXPECT_FALSE(lanes.carries(InstanceHandle_t(writer_guid(1)), 1));
}

TEST(LaneAssignmentTest, ASecondLaneWithoutWritersDoesNotCarryTheFirstLanesWriter) {
    // A lane declared after the publisher had lane 0: its reader matches the publisher as well.
    LaneAssignment lanes;
    lanes.assign(writer_guid(1), 0);
    lanes.several_lanes();
    EXPECT_TRUE(lanes.carries(InstanceHandle_t(writer_guid(1)), 0));
    EXPECT_FALSE(lanes.carries(InstanceHandle_t(writer_guid(1)), 1));
    EXPECT_TRUE(lanes.carries(InstanceHandle_t(writer_guid(2)), 1)) << "until it is assigned, whichever lane has it";
}

TEST(LaneAssignmentTest, AReleasedWriterNamesItsLaneOnceAndLeavesTheCount) {
    LaneAssignment lanes;
    lanes.assign(writer_guid(1), 1);
    lanes.assign(writer_guid(2), 1);
    EXPECT_EQ(lanes.writers_on(1), 2u);
    EXPECT_EQ(lanes.release(writer_guid(1)), std::optional<std::uint16_t>(1));
    EXPECT_EQ(lanes.release(writer_guid(1)), std::nullopt);
    EXPECT_EQ(lanes.writers_on(1), 1u);
}

}  // namespace
}  // namespace tgw::passthrough
