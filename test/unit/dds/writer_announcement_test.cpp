// Reading the topic of a writer's announcement (SEDP DATA(w)) out of an RTPS message.
#include "gateway/dds/writer_announcement.hpp"

#include <gtest/gtest.h>

#include "test/unit/wire/rtps_bytes.hpp"

namespace tgw::dds {
namespace {

using test::rtps::Bytes;
namespace rtps = test::rtps;

using rtps::announcement_data;
using rtps::publication;
using rtps::PUBLICATIONS;

TEST(WriterAnnouncementTest, ReadsTheTopicOfAPublicationAsFastDdsSendsIt) {
    const Bytes message =
        rtps::message({rtps::info_dst(0x03), rtps::info_ts(0x01),
                       announcement_data(publication("rover1/telemetry/A", true), 9), rtps::statistics(0x00)});
    const auto found = writer_announcements(message.data(), message.size());
    ASSERT_TRUE(found);
    ASSERT_EQ(found->count, 1u);
    EXPECT_EQ(found->topics[0], "rover1/telemetry/A");
    EXPECT_EQ(found->first.writer, PUBLICATIONS);
    EXPECT_EQ(found->first.sequence, 9);
}

TEST(WriterAnnouncementTest, ReadsABigEndianParameterListAndSkipsInlineQos) {
    const Bytes message = rtps::message({announcement_data(publication("hazard", false), 2, true)});
    const auto found = writer_announcements(message.data(), message.size());
    ASSERT_TRUE(found);
    EXPECT_EQ(found->topics[0], "hazard");
}

TEST(WriterAnnouncementTest, ReadsSeveralAnnouncementsAndTheHeartbeatAfterThem) {
    const Bytes message = rtps::message({rtps::info_dst(0x03), announcement_data(publication("picture", true), 4),
                                         announcement_data(publication("hazard", true), 5), rtps::heartbeat(0x03, 5)});
    const auto found = writer_announcements(message.data(), message.size());
    ASSERT_TRUE(found);
    ASSERT_EQ(found->count, 2u);
    EXPECT_EQ(found->topics[0], "picture");
    EXPECT_EQ(found->topics[1], "hazard");
    EXPECT_EQ(found->first.sequence, 4);
}

TEST(WriterAnnouncementTest, IgnoresWhatIsNotAWritersAnnouncementAlone) {
    const Bytes payload = publication("hazard", true);
    const auto none = [](const Bytes& message) { return !writer_announcements(message.data(), message.size()); };
    EXPECT_TRUE(none(rtps::message({rtps::data_of({0x00, 0x00, 0x04, 0xc2}, 1)})));  // a reader's (DATA(r))
    EXPECT_TRUE(none(rtps::message({rtps::data_of({0x00, 0x00, 0x01, 0x03}, 1)})));  // a user sample
    EXPECT_TRUE(none(rtps::message({announcement_data(payload), rtps::acknack()})));
    EXPECT_TRUE(none(rtps::message({announcement_data(payload), rtps::data_of({0x00, 0x00, 0x01, 0x03}, 1)})));
    Bytes cut = rtps::message({announcement_data(payload)});
    cut.resize(cut.size() - 12);  // the topic's string runs past the message's end
    EXPECT_TRUE(none(cut));
    Bytes no_topic{0x00, 0x03, 0, 0};
    rtps::put_parameter(no_topic, 0x0001, {}, true);
    EXPECT_TRUE(none(rtps::message({announcement_data(no_topic)})));
    EXPECT_TRUE(none(Bytes{'R', 'T', 'P'}));
}

}  // namespace
}  // namespace tgw::dds
