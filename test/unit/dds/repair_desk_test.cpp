// RepairDesk: which of the WAN participant's messages wait for the schedule as repairs, and what becomes of them.
#include "gateway/dds/repair_desk.hpp"

#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <mutex>
#include <vector>

#include "core/wire_model.hpp"
#include "test/fakes/fake_clock.hpp"
#include "test/unit/wire/rtps_bytes.hpp"

namespace tgw::dds {
namespace {

using namespace std::chrono_literals;
namespace rtps = test::rtps;

constexpr std::array<std::uint8_t, 4> WRITER{0x00, 0x00, 0x07, 0x03};

class CountingSender final : public DatagramSender {
  public:
    bool send_datagram(const DatagramDestination&, const std::uint8_t* bytes, std::size_t size) override {
        sent.emplace_back(bytes, bytes + size);
        return true;
    }
    std::vector<rtps::Bytes> sent;
};

DatagramDestination reader_at(std::uint32_t port) {
    static const int channel = 0;
    eprosima::fastrtps::rtps::Locator_t locator;
    locator.kind = LOCATOR_KIND_UDPv4;
    locator.port = port;
    return {&channel, {locator}};
}

class RepairDeskTest : public ::testing::Test {
  protected:
    RepairDeskTest() {
        sut.set_submit([this](const core::Repair& repair) { submitted.push_back(repair); });
    }

    /// A scheduled write of sample `sequence` of topic 5, due in `due_in`: its message, as the transport sees it.
    void write(std::int64_t sequence, base::Duration due_in = 2s) {
        const RepairDesk::WriteScope scope(5, clock.now() + due_in, true);
        EXPECT_FALSE(write_message(sequence, 1)) << "a write's first message is sent";
    }
    /// A scheduled write's message carrying fragment `fragment` of sample `sequence`, to `copies` readers: true
    /// when the desk holds it.
    bool write_message(std::int64_t sequence, std::uint32_t fragment, std::size_t copies = 1) {
        const rtps::Bytes message = rtps::message({rtps::info_ts(1), rtps::data_frag(WRITER, sequence, fragment)});
        return sut.note_scheduled(sender, reader_at(7411), message.data(), message.size(), copies,
                                  message.size() + core::WireModel::FRAME_HEADER_BYTES);
    }
    /// Fast DDS sends fragment `fragment` of sample `sequence` again, outside any write.
    bool resend(std::int64_t sequence, std::uint32_t fragment = 2, std::uint32_t port = 7411) {
        return resent(sequence, fragment, port) == RepairDesk::Verdict::held;
    }
    RepairDesk::Verdict resent(std::int64_t sequence, std::uint32_t fragment = 2, std::uint32_t port = 7411) {
        const rtps::Bytes message = rtps::message({rtps::info_ts(1), rtps::data_frag(WRITER, sequence, fragment)});
        return sut.hold(sender, reader_at(port), message.data(), message.size(), 1, gap);
    }

    test::FakeClock clock;
    std::shared_ptr<DatagramCoalescer> coalescer =
        std::make_shared<DatagramCoalescer>(std::chrono::microseconds(0), 1472, clock);
    RepairDesk sut{coalescer, clock};
    CountingSender sender;
    std::vector<core::Repair> submitted;
    std::vector<std::uint8_t> gap;
};

TEST_F(RepairDeskTest, HoldsARepairOfAScheduledSampleWithItsTopicAndDeadline) {
    write(3, 2s);
    ASSERT_TRUE(resend(3));
    ASSERT_EQ(submitted.size(), 1u);
    EXPECT_EQ(submitted[0].topic, 5u);
    EXPECT_EQ(submitted[0].deadline, clock.now() + 2s);
    const std::size_t message_bytes = rtps::message({rtps::info_ts(1), rtps::data_frag(WRITER, 3, 2)}).size();
    EXPECT_EQ(submitted[0].wire_bits, 8u * (message_bytes + core::WireModel::FRAME_HEADER_BYTES));
    EXPECT_TRUE(sender.sent.empty()) << "held, not sent";
}

TEST_F(RepairDeskTest, SendsAHeldRepairWhenTheScheduleSaysSo) {
    write(3);
    ASSERT_TRUE(resend(3));
    sut.send(submitted[0].id);
    ASSERT_EQ(sender.sent.size(), 1u);
    EXPECT_EQ(sender.sent[0], rtps::message({rtps::info_ts(1), rtps::data_frag(WRITER, 3, 2)}));
    EXPECT_EQ(sut.counts().sent, 1u);
}

TEST_F(RepairDeskTest, ForgetsADiscardedRepair) {
    write(3);
    ASSERT_TRUE(resend(3));
    sut.discard(submitted[0].id);
    sut.send(submitted[0].id);
    EXPECT_TRUE(sender.sent.empty());
    EXPECT_EQ(sut.counts().discarded, 1u);
}

TEST_F(RepairDeskTest, LetsGoWhatNoScheduledWriteSent) {
    EXPECT_EQ(resent(9), RepairDesk::Verdict::send) << "not a sample the gateway wrote (discovery, another writer)";
    EXPECT_TRUE(submitted.empty());
}

TEST_F(RepairDeskTest, AnswersARepairOfASamplePastItsDeadlineWithAGap) {
    write(3, 1s);
    clock.advance(1s);
    EXPECT_EQ(resent(3), RepairDesk::Verdict::gap) << "Fast DDS may still have it; the reader has no use for it";
    EXPECT_EQ(gap, rtps::message({rtps::gap(WRITER, 3)}));
    clock.advance(2s);  // pruned from what the desk remembers
    EXPECT_EQ(resent(3, 3), RepairDesk::Verdict::gap);
    EXPECT_EQ(sut.counts().gapped, 2u);
    EXPECT_TRUE(submitted.empty());
}

TEST_F(RepairDeskTest, ALatchedWritersSamplePastItsDeadlineStillGoesToALateJoiner) {
    {
        const RepairDesk::WriteScope scope(5, clock.now() + 1s, true, true);
        EXPECT_FALSE(write_message(3, 1));
    }
    clock.advance(5s);
    EXPECT_EQ(resent(3), RepairDesk::Verdict::send) << "transient local: its history is for late joiners";
    EXPECT_EQ(sut.counts().gapped, 0u);
}

TEST_F(RepairDeskTest, ForgetsARepeatOfARepairItHolds) {
    write(3);
    ASSERT_TRUE(resend(3));
    EXPECT_TRUE(resend(3)) << "asked again at the next HEARTBEAT while the first still waits";
    EXPECT_TRUE(resend(3, 3)) << "another fragment is another repair";
    EXPECT_TRUE(resend(3, 2, 7413)) << "so is the same fragment to another reader";
    EXPECT_EQ(submitted.size(), 3u);
    EXPECT_EQ(sut.counts().repeats, 1u);
}

TEST_F(RepairDeskTest, HoldsNothingOnceStopped) {
    write(3);
    ASSERT_TRUE(resend(3));
    sut.stop();
    EXPECT_FALSE(resend(3, 3));
    sut.send(submitted[0].id);
    EXPECT_TRUE(sender.sent.empty()) << "what it held went with it";
}

TEST_F(RepairDeskTest, HoldsAWritesFragmentsAfterItsFirstAsContinuationsWhilePacing) {
    sut.pace_fragments(true);
    {
        const RepairDesk::WriteScope scope(5, clock.now() + 20s, false);
        EXPECT_FALSE(write_message(3, 1)) << "the first fragment leaves with the write";
        EXPECT_TRUE(write_message(3, 2, 2));
        EXPECT_TRUE(write_message(3, 3, 2));
    }
    ASSERT_EQ(submitted.size(), 2u);
    const std::size_t message_bytes = rtps::message({rtps::info_ts(1), rtps::data_frag(WRITER, 3, 2)}).size();
    for (const core::Repair& continuation : submitted) {
        EXPECT_EQ(continuation.kind, core::Repair::Kind::continuation);
        EXPECT_EQ(continuation.topic, 5u);
        EXPECT_EQ(continuation.deadline, clock.now() + 20s);
        EXPECT_EQ(continuation.wire_bits, 2u * 8u * (message_bytes + core::WireModel::FRAME_HEADER_BYTES))
            << "both copies, sent when it leaves";
        EXPECT_EQ(continuation.prepaid_bits, 8u * (message_bytes + core::WireModel::FRAME_HEADER_BYTES))
            << "the one copy the write was charged for";
    }
    EXPECT_EQ(sut.counts().continuations_held, 2u);
    sut.send(submitted[1].id);
    sut.send(submitted[0].id);
    ASSERT_EQ(sender.sent.size(), 2u);
    EXPECT_EQ(sender.sent[0], rtps::message({rtps::info_ts(1), rtps::data_frag(WRITER, 3, 3)})) << "as told";
}

TEST_F(RepairDeskTest, SendsAWholeWriteAtOnceWhenNotPacing) {
    const RepairDesk::WriteScope scope(5, clock.now() + 20s, true);
    EXPECT_FALSE(write_message(3, 1));
    EXPECT_FALSE(write_message(3, 2)) << "a fast link: the fragments leave together";
    EXPECT_TRUE(submitted.empty());
    EXPECT_TRUE(resend(3)) << "still remembered for its repairs";
}

TEST_F(RepairDeskTest, PacesOnlyTheWrittenSamplesFragments) {
    sut.pace_fragments(true);
    const RepairDesk::WriteScope scope(5, clock.now() + 20s, false);
    EXPECT_FALSE(write_message(3, 1));
    EXPECT_FALSE(write_message(2, 4)) << "another sample's fragment in the write (a repair Fast DDS sends with it)";
    const rtps::Bytes whole = rtps::message({rtps::info_ts(1), rtps::data_of(WRITER, 4)});
    EXPECT_FALSE(sut.note_scheduled(sender, reader_at(7411), whole.data(), whole.size(), 1, whole.size()));
    EXPECT_TRUE(submitted.empty());
}

TEST_F(RepairDeskTest, ARepairOfAFragmentStillHeldAsAContinuationIsARepeat) {
    sut.pace_fragments(true);
    {
        const RepairDesk::WriteScope scope(5, clock.now() + 20s, true);
        EXPECT_FALSE(write_message(3, 1));
        EXPECT_TRUE(write_message(3, 2));
    }
    EXPECT_TRUE(resend(3, 2)) << "the held continuation carries it";
    EXPECT_EQ(submitted.size(), 1u);
    EXPECT_EQ(sut.counts().repeats, 1u);
}

constexpr std::array<std::uint8_t, 4> SPDP_WRITER{0x00, 0x01, 0x00, 0xc2};

/// Fast DDS's announcement (SPDP) `sequence`, to the base-camp ports `ports`, as the transport sees it.
bool announce(
    RepairDesk& desk, DatagramSender& sender, std::int64_t sequence, const std::vector<std::uint32_t>& ports,
    const RepairDesk::LocatorFilter& supported = [](const auto&) { return true; }) {
    DatagramDestination destination = reader_at(ports.front());
    for (std::size_t i = 1; i < ports.size(); ++i) {
        destination.locators.push_back(reader_at(ports[i]).locators.front());
    }
    const rtps::Bytes message = rtps::message({rtps::info_ts(1), rtps::data_of(SPDP_WRITER, sequence)});
    return desk.hold_announcement(sender, destination, message.data(), message.size(), supported);
}

TEST_F(RepairDeskTest, HoldsAnAnnouncementAsOneCopyPerLocatorForTheSchedule) {
    ASSERT_TRUE(announce(sut, sender, 1, {7400, 7400, 7402, 7404, 7406}));
    ASSERT_EQ(submitted.size(), 4u) << "one copy per port; the port Fast DDS listed twice once";
    const std::size_t message_bytes = rtps::message({rtps::info_ts(1), rtps::data_of(SPDP_WRITER, 1)}).size();
    for (std::size_t i = 0; i < submitted.size(); ++i) {
        EXPECT_EQ(submitted[i].kind, core::Repair::Kind::announcement);
        EXPECT_EQ(submitted[i].deadline, clock.now() + core::ANNOUNCEMENT_WAIT + i * 250ms)
            << "the copies the schedule found no room for leave one at a time";
        EXPECT_EQ(submitted[i].wire_bits, 8u * (message_bytes + core::WireModel::FRAME_HEADER_BYTES));
    }
    EXPECT_TRUE(sender.sent.empty()) << "held, not sent";
    sut.send(submitted[2].id);
    ASSERT_EQ(sender.sent.size(), 1u);
    EXPECT_EQ(sut.counts().announcements_held, 4u);
}

TEST_F(RepairDeskTest, ANewerAnnouncementReplacesTheCopyStillHeldForItsLocator) {
    ASSERT_TRUE(announce(sut, sender, 1, {7400, 7402}));
    ASSERT_TRUE(announce(sut, sender, 2, {7400, 7404}));
    EXPECT_EQ(submitted.size(), 3u) << "7400 once";
    EXPECT_EQ(sut.counts().announcements_replaced, 1u);
    sut.send(submitted[0].id);
    ASSERT_EQ(sender.sent.size(), 1u);
    EXPECT_EQ(sender.sent[0], rtps::message({rtps::info_ts(1), rtps::data_of(SPDP_WRITER, 2)})) << "the newer";
}

TEST_F(RepairDeskTest, AnAnnouncementOnlyToLocatorsTheTransportDoesNotServeOrAnotherMessageIsNotHeld) {
    EXPECT_FALSE(announce(sut, sender, 1, {7400}, [](const auto&) { return false; })) << "shared memory, say";
    write(3);
    const rtps::Bytes repair = rtps::message({rtps::info_ts(1), rtps::data_frag(WRITER, 3, 2)});
    EXPECT_FALSE(sut.hold_announcement(sender, reader_at(7411), repair.data(), repair.size(), [](const auto&) {
        return true;
    })) << "a repair is hold()'s";
    EXPECT_TRUE(submitted.empty());
}

TEST_F(RepairDeskTest, LetsTheScheduleLeaveOutAtMostTwoAnnouncementsInARowToAPort) {
    std::vector<bool> skippable;
    for (std::int64_t k = 1; k <= 4; ++k) {
        ASSERT_TRUE(announce(sut, sender, k, {7400}));
        skippable.push_back(submitted.back().skippable);
        sut.discard(submitted.back().id);  // left out
    }
    EXPECT_EQ(skippable, (std::vector<bool>{true, true, false, false}));
    sut.send(submitted.back().id);  // already discarded: nothing
    ASSERT_TRUE(announce(sut, sender, 5, {7400}));
    sut.send(submitted.back().id);
    ASSERT_TRUE(announce(sut, sender, 6, {7400}));
    EXPECT_TRUE(submitted.back().skippable) << "one sent: the count starts again";
    ASSERT_TRUE(announce(sut, sender, 7, {7402}));
    EXPECT_TRUE(submitted.back().skippable) << "another port counts its own";
}

TEST(RepairDeskAnnouncementsOnlyTest, HoldsAnnouncementsButNoRepairs) {
    test::FakeClock clock;
    RepairDesk desk(std::make_shared<DatagramCoalescer>(std::chrono::microseconds(0), 1472, clock), clock, false);
    std::vector<core::Repair> submitted;
    desk.set_submit([&](const core::Repair& repair) { submitted.push_back(repair); });
    CountingSender sender;
    desk.pace_fragments(true);
    const RepairDesk::WriteScope scope(5, clock.now() + 2s, true);
    const rtps::Bytes written = rtps::message({rtps::info_ts(1), rtps::data_frag(WRITER, 3, 1)});
    desk.note_scheduled(sender, reader_at(7411), written.data(), written.size(), 1, written.size());
    const rtps::Bytes rest = rtps::message({rtps::info_ts(1), rtps::data_frag(WRITER, 3, 2)});
    EXPECT_FALSE(desk.note_scheduled(sender, reader_at(7411), rest.data(), rest.size(), 1, rest.size()))
        << "compact mode's bundles are its own chunks";
    const rtps::Bytes repair = rtps::message({rtps::info_ts(1), rtps::data_frag(WRITER, 3, 2)});
    std::vector<std::uint8_t> gap;
    EXPECT_EQ(desk.hold(sender, reader_at(7411), repair.data(), repair.size(), 1, gap), RepairDesk::Verdict::send)
        << "compact mode's";
    EXPECT_TRUE(announce(desk, sender, 1, {7400}));
    EXPECT_EQ(submitted.size(), 1u);
}

TEST_F(RepairDeskTest, HoldsAScheduledTopicsWriterAnnouncementInItsUrgencyAndForgetsARepeat) {
    sut.set_topic_lookup([](std::string_view topic) -> std::optional<RepairDesk::ScheduledTopic> {
        if (topic == "rover1/hazard") {
            return RepairDesk::ScheduledTopic{3, 1s};
        }
        return std::nullopt;
    });
    const auto announce = [&](const std::string& topic, std::int64_t sequence) {
        const rtps::Bytes message =
            rtps::message({rtps::info_dst(2), rtps::announcement_data(rtps::publication(topic, true), sequence)});
        return sut.hold_writer_announcement(sender, reader_at(7411), message.data(), message.size(), 1);
    };
    ASSERT_TRUE(announce("rover1/hazard", 4));
    ASSERT_EQ(submitted.size(), 1u);
    EXPECT_EQ(submitted[0].kind, core::Repair::Kind::writer_announcement);
    EXPECT_EQ(submitted[0].topic, 3u);
    EXPECT_EQ(submitted[0].deadline, clock.now() + 1s) << "its TTL, shorter than the announcements' wait";
    EXPECT_TRUE(announce("rover1/hazard", 4)) << "the camp asked again while it waits";
    EXPECT_EQ(submitted.size(), 1u);
    EXPECT_FALSE(announce("tgw/status", 5)) << "not a scheduled topic: sent now";
    sut.send(submitted[0].id);
    EXPECT_EQ(sender.sent.size(), 1u);
    EXPECT_EQ(sut.counts().writer_announcements_held, 1u);
}

}  // namespace
}  // namespace tgw::dds
