// DatagramCoalescer: which WAN messages go at once and which wait to share a datagram, on a fake clock.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>
#include <vector>

#include "core/wire_model.hpp"
#include "gateway/dds/datagram_coalescer.hpp"
#include "test/fakes/fake_clock.hpp"
#include "test/unit/wire/rtps_bytes.hpp"

namespace tgw::dds {
namespace {

using namespace std::chrono_literals;
using test::rtps::Bytes;
using test::rtps::data;
using test::rtps::info_dst;
using test::rtps::info_ts;
using test::rtps::message;

/// Keeps every datagram it is asked to send.
class RecordingSender final : public DatagramSender {
  public:
    struct Sent {
        DatagramDestination destination;
        Bytes bytes;
    };

    bool send_datagram(const DatagramDestination& destination, const std::uint8_t* bytes, std::size_t size) override {
        std::lock_guard<std::mutex> lock(mutex_);
        sent_.push_back({destination, Bytes(bytes, bytes + size)});
        return succeed;
    }

    std::vector<Sent> sent() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return sent_;
    }

    bool succeed = true;

  private:
    mutable std::mutex mutex_;
    std::vector<Sent> sent_;
};

DatagramDestination destination(std::uint32_t port) {
    static const int channel = 0;
    eprosima::fastrtps::rtps::Locator_t locator;
    locator.kind = LOCATOR_KIND_UDPv4;
    locator.port = port;
    return {&channel, {locator}};
}

/// The message of sample `i`: an INFO_TS and a DATA of 40 bytes.
Bytes sample(std::uint8_t i) {
    return message({info_ts(i), data(40)});
}

/// One write of the gateway, of sample `i`: its messages may wait.
bool write_sample(DatagramCoalescer& coalescer, DatagramSender& sender, std::uint8_t i, const DatagramDestination& to) {
    const DatagramCoalescer::DeferScope scope;
    const Bytes m = sample(i);
    return coalescer.send(sender, to, m.data(), m.size());
}

class DatagramCoalescerTest : public ::testing::Test {
  protected:
    bool write(std::uint8_t i, const DatagramDestination& to) { return write_sample(sut, sender, i, to); }

    /// The RTPS header and both samples' submessages in one datagram.
    static Bytes packed(const Bytes& first, const Bytes& second) {
        Bytes out = first;
        out.insert(out.end(), second.begin() + wire::RtpsDatagram::HEADER_BYTES, second.end());
        return out;
    }

    test::FakeClock clock;
    RecordingSender sender;
    const DatagramDestination base_camp = destination(7411);
    DatagramCoalescer sut{100us, 1472, clock};
};

TEST_F(DatagramCoalescerTest, SendsASampleThatComesAloneAtOnce) {
    ASSERT_TRUE(write(1, base_camp));
    ASSERT_EQ(sender.sent().size(), 1u);
    EXPECT_EQ(sender.sent()[0].bytes, sample(1));
    EXPECT_EQ(sender.sent()[0].destination, base_camp);

    clock.advance(100us);
    ASSERT_TRUE(write(2, base_camp));
    EXPECT_EQ(sender.sent().size(), 2u);
}

TEST_F(DatagramCoalescerTest, HoldsASampleThatFollowsCloselyUntilItsWindowEnds) {
    write(1, base_camp);
    clock.advance(10us);
    ASSERT_TRUE(write(2, base_camp));
    EXPECT_EQ(sender.sent().size(), 1u);

    clock.advance(99us);
    sut.flush_due();
    EXPECT_EQ(sender.sent().size(), 1u);
    clock.advance(1us);
    sut.flush_due();
    ASSERT_EQ(sender.sent().size(), 2u);
    EXPECT_EQ(sender.sent()[1].bytes, sample(2));
}

TEST_F(DatagramCoalescerTest, PacksTheSamplesOfABurstIntoOneDatagram) {
    write(1, base_camp);
    for (std::uint8_t i = 2; i <= 4; ++i) {
        clock.advance(10us);
        write(i, base_camp);
    }
    clock.advance(100us);
    sut.flush_due();

    ASSERT_EQ(sender.sent().size(), 2u);
    EXPECT_EQ(sender.sent()[1].bytes, packed(packed(sample(2), sample(3)), sample(4)));
    const auto counts = sut.counts();
    EXPECT_EQ(counts.messages, 4u);
    EXPECT_EQ(counts.datagrams, 2u);
    EXPECT_EQ(counts.failed_datagrams, 0u);
}

TEST_F(DatagramCoalescerTest, SendsAFullDatagramAtOnce) {
    DatagramCoalescer small{100us, 2 * sample(1).size(), clock};
    write_sample(small, sender, 1, base_camp);
    clock.advance(10us);
    write_sample(small, sender, 2, base_camp);
    write_sample(small, sender, 3, base_camp);
    EXPECT_EQ(sender.sent().size(), 1u);  // 2 and 3 fit in one datagram
    write_sample(small, sender, 4, base_camp);
    ASSERT_EQ(sender.sent().size(), 2u);  // 4 did not fit: 2 and 3 went
    EXPECT_EQ(sender.sent()[1].bytes, packed(sample(2), sample(3)));
}

// A 64 KiB sample's first fragment fills a 65,500-byte datagram: holding it only cost a copy and a thread's wake-up.
TEST_F(DatagramCoalescerTest, SendsAMessageThatFillsItsDatagramAtOnceAfterWhatWaits) {
    const Bytes full = message({info_ts(3), data(1400)});
    ASSERT_LE(full.size(), 1472u);
    ASSERT_GT(full.size() + 1472u / 16, 1472u);
    write(1, base_camp);
    clock.advance(10us);
    write(2, base_camp);  // within the window: waits
    {
        const DatagramCoalescer::DeferScope scope;
        ASSERT_TRUE(sut.send(sender, base_camp, full.data(), full.size()));
        const Bytes tail = sample(4);  // the rest of the same write follows it
        ASSERT_TRUE(sut.send(sender, base_camp, tail.data(), tail.size()));
    }
    const auto sent = sender.sent();
    ASSERT_EQ(sent.size(), 4u);
    EXPECT_EQ(sent[1].bytes, sample(2));
    EXPECT_EQ(sent[2].bytes, full);
    EXPECT_EQ(sent[3].bytes, sample(4));
}

TEST_F(DatagramCoalescerTest, AMessageWithRoomLeftStillWaitsForItsWindow) {
    const Bytes large = message({info_ts(3), data(1200)});
    ASSERT_LE(large.size() + 1472u / 16, 1472u);
    write(1, base_camp);
    clock.advance(10us);
    const DatagramCoalescer::DeferScope scope;
    sut.send(sender, base_camp, large.data(), large.size());
    EXPECT_EQ(sender.sent().size(), 1u);
}

TEST_F(DatagramCoalescerTest, SendsEveryMessageOfAWriteAtOnceWhenItsFirstWentAtOnce) {
    // A large sample's fragments: one write, several messages.
    const DatagramCoalescer::DeferScope scope;
    for (std::uint8_t i = 1; i <= 3; ++i) {
        const Bytes m = sample(i);
        sut.send(sender, base_camp, m.data(), m.size());
    }
    EXPECT_EQ(sender.sent().size(), 3u);
}

TEST_F(DatagramCoalescerTest, SendsWhatWaitsBeforeAMessageFromOutsideAWrite) {
    write(1, base_camp);
    clock.advance(10us);
    write(2, base_camp);
    const Bytes heartbeat = message({test::rtps::submessage(0x07, 0x01, Bytes(28, 0))});
    ASSERT_TRUE(sut.send(sender, base_camp, heartbeat.data(), heartbeat.size()));

    ASSERT_EQ(sender.sent().size(), 3u);
    EXPECT_EQ(sender.sent()[1].bytes, sample(2));
    EXPECT_EQ(sender.sent()[2].bytes, heartbeat);
}

TEST_F(DatagramCoalescerTest, KeepsDestinationsApart) {
    const DatagramDestination other_camp = destination(7511);
    write(1, base_camp);
    clock.advance(10us);
    write(2, other_camp);  // nothing went there yet: at once
    write(3, base_camp);   // waits
    ASSERT_EQ(sender.sent().size(), 2u);
    EXPECT_EQ(sender.sent()[1].destination, other_camp);

    clock.advance(100us);
    sut.flush_due();
    ASSERT_EQ(sender.sent().size(), 3u);
    EXPECT_EQ(sender.sent()[2].destination, base_camp);
    EXPECT_EQ(sender.sent()[2].bytes, sample(3));
}

TEST_F(DatagramCoalescerTest, SendsEverythingAtOnceWithAZeroWindow) {
    DatagramCoalescer off{0us, 1472, clock};
    for (std::uint8_t i = 1; i <= 3; ++i) {
        write_sample(off, sender, i, base_camp);
    }
    EXPECT_EQ(sender.sent().size(), 3u);
    EXPECT_EQ(off.counts().messages, 3u);
    EXPECT_EQ(off.counts().datagrams, 3u);
}

TEST_F(DatagramCoalescerTest, StopSendsWhatWaitsAndThenEverythingGoesAtOnce) {
    write(1, base_camp);
    clock.advance(10us);
    write(2, base_camp);
    sut.stop();
    EXPECT_EQ(sender.sent().size(), 2u);
    write(3, base_camp);
    EXPECT_EQ(sender.sent().size(), 3u);
}

TEST_F(DatagramCoalescerTest, CountsADatagramThatWaitedAndFailed) {
    write(1, base_camp);
    clock.advance(10us);
    sender.succeed = false;
    ASSERT_TRUE(write(2, base_camp));  // the writer is told it went
    clock.advance(100us);
    sut.flush_due();
    EXPECT_EQ(sut.counts().failed_datagrams, 1u);
}

/// A coalescer that holds a reliable writer's HEARTBEATs and GAPs alone for 250 ms, and adds up what it charges.
class HeldControlTest : public DatagramCoalescerTest {
  protected:
    bool hold(const Bytes& m, const DatagramDestination& to, std::size_t copies = 1) {
        return held.hold(sender, to, m.data(), m.size(), copies);
    }
    /// A write of sample `i` to one participant, whose message names it first as Fast DDS's do.
    bool write_held(std::uint8_t i, const DatagramDestination& to) {
        const DatagramCoalescer::DeferScope scope;
        const Bytes m = addressed(i);
        return held.send(sender, to, m.data(), m.size());
    }
    static Bytes addressed(std::uint8_t i) { return message({info_dst(0x33), info_ts(i), data(40)}); }

    /// What a message to the same participant leaves out when it joins another: its header and its INFO_DST.
    static constexpr std::size_t SHARED_BYTES = wire::RtpsDatagram::HEADER_BYTES + 16;
    static Bytes joined(const Bytes& first, const Bytes& second) {
        Bytes out = first;
        out.insert(out.end(), second.begin() + SHARED_BYTES, second.end());
        return out;
    }

    /// A lone HEARTBEAT to one participant, as Fast DDS sends a writer's periodic one (its statistics left out).
    const Bytes heartbeat = message({info_dst(0x33), test::rtps::heartbeat()});
    std::uint64_t charged = 0;
    DatagramCoalescer held{100us, 1472, clock, HeldControl{250ms, [this](std::uint64_t bytes) { charged += bytes; }}};
};

TEST_F(HeldControlTest, AHeartbeatAloneRidesInTheDatagramOfTheNextSample) {
    ASSERT_TRUE(hold(heartbeat, base_camp));
    EXPECT_TRUE(sender.sent().empty());
    clock.advance(40ms);
    ASSERT_TRUE(write_held(1, base_camp));

    ASSERT_EQ(sender.sent().size(), 1u) << "the sample goes at once, the HEARTBEAT with it";
    EXPECT_EQ(sender.sent()[0].bytes, joined(heartbeat, addressed(1)));
    // The sample is charged as if alone; in one datagram with it the HEARTBEAT costs its own submessage.
    EXPECT_EQ(charged, heartbeat.size() - SHARED_BYTES);
    const auto counts = held.counts();
    EXPECT_EQ(counts.controls_held, 1u);
    EXPECT_EQ(counts.controls_rode, 1u);
}

TEST_F(HeldControlTest, AHeartbeatNothingFollowsLeavesAloneAtTheEndOfItsWait) {
    hold(heartbeat, base_camp);
    clock.advance(249ms);
    held.flush_due();
    EXPECT_TRUE(sender.sent().empty());
    clock.advance(1ms);
    held.flush_due();

    ASSERT_EQ(sender.sent().size(), 1u);
    EXPECT_EQ(sender.sent()[0].bytes, heartbeat);
    EXPECT_EQ(charged, heartbeat.size() + core::WireModel::FRAME_HEADER_BYTES) << "a datagram of its own";
    EXPECT_EQ(held.counts().controls_rode, 0u);
}

TEST_F(HeldControlTest, SeveralWritersHeartbeatsShareOneDatagram) {
    const Bytes other = message({info_dst(0x33), test::rtps::heartbeat(0x21)});
    hold(heartbeat, base_camp);
    clock.advance(100ms);
    hold(other, base_camp);
    clock.advance(150ms);  // the first one's wait ends: both go
    held.flush_due();

    ASSERT_EQ(sender.sent().size(), 1u);
    EXPECT_EQ(sender.sent()[0].bytes, joined(heartbeat, other));
    EXPECT_EQ(charged, joined(heartbeat, other).size() + core::WireModel::FRAME_HEADER_BYTES);
}

TEST_F(HeldControlTest, AMessageFromOutsideAWriteTakesItAlong) {
    hold(heartbeat, base_camp);
    const Bytes repair = message({info_dst(0x33), info_ts(9), data(40)});
    ASSERT_TRUE(held.send(sender, base_camp, repair.data(), repair.size()));

    ASSERT_EQ(sender.sent().size(), 1u);
    EXPECT_EQ(sender.sent()[0].bytes, joined(heartbeat, repair));
}

TEST_F(HeldControlTest, RidesWithSamplesWaitingForTheirWindow) {
    write_held(1, base_camp);
    clock.advance(10us);
    write_held(2, base_camp);  // waits for its window
    hold(heartbeat, base_camp);
    clock.advance(100us);
    held.flush_due();

    ASSERT_EQ(sender.sent().size(), 2u);
    // The HEARTBEAT's message sets no timestamp: the sample's is invalidated before it.
    Bytes expected = addressed(2);
    expected.insert(expected.end(), {0x09, 0x03, 0x00, 0x00});
    expected.insert(expected.end(), heartbeat.begin() + SHARED_BYTES, heartbeat.end());
    EXPECT_EQ(sender.sent()[1].bytes, expected);
    EXPECT_EQ(charged, 4 + heartbeat.size() - SHARED_BYTES);
}

TEST_F(HeldControlTest, WaitsOnlyForItsOwnDestination) {
    hold(heartbeat, base_camp);
    write_held(1, destination(7413));
    ASSERT_EQ(sender.sent().size(), 1u);
    EXPECT_EQ(sender.sent()[0].bytes, addressed(1));
    EXPECT_EQ(charged, 0u) << "still held";
}

TEST_F(HeldControlTest, ChargesEveryCopy) {
    hold(heartbeat, base_camp, 2);
    write_held(1, base_camp);
    EXPECT_EQ(charged, 2 * (heartbeat.size() - SHARED_BYTES));
}

TEST_F(HeldControlTest, StopSendsWhatIsHeld) {
    hold(heartbeat, base_camp);
    held.stop();
    ASSERT_EQ(sender.sent().size(), 1u);
    EXPECT_EQ(sender.sent()[0].bytes, heartbeat);
    EXPECT_EQ(charged, heartbeat.size() + core::WireModel::FRAME_HEADER_BYTES);
}

TEST_F(HeldControlTest, WithoutAWaitItGoesAtOnce) {
    std::uint64_t at_once_charged = 0;
    DatagramCoalescer at_once{100us, 1472, clock, HeldControl{{}, [&](std::uint64_t b) { at_once_charged += b; }}};
    EXPECT_FALSE(at_once.holds_control());
    ASSERT_TRUE(at_once.hold(sender, base_camp, heartbeat.data(), heartbeat.size(), 1));
    ASSERT_EQ(sender.sent().size(), 1u);
    EXPECT_EQ(at_once_charged, heartbeat.size() + core::WireModel::FRAME_HEADER_BYTES);
}

TEST(DatagramCoalescerThreadTest, TheFlushThreadSendsWhenTheWindowEnds) {
    const base::SystemClock clock;
    RecordingSender sender;
    DatagramCoalescer sut{200us, 1472, clock};
    sut.start();
    const DatagramDestination to = destination(7411);
    write_sample(sut, sender, 1, to);
    write_sample(sut, sender, 2, to);
    // The second waits for the thread, which must send it about 200 us later; allow for a loaded machine.
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (sender.sent().size() < 2 && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(1ms);
    }
    EXPECT_EQ(sender.sent().size(), 2u);
    sut.stop();
}

}  // namespace
}  // namespace tgw::dds
