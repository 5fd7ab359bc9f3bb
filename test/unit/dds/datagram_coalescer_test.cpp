// DatagramCoalescer: which WAN messages go at once and which wait to share a datagram, on a fake clock.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>
#include <vector>

#include "gateway/dds/datagram_coalescer.hpp"
#include "test/fakes/fake_clock.hpp"
#include "test/unit/dds/rtps_bytes.hpp"

namespace tgw::dds {
namespace {

using namespace std::chrono_literals;
using test::rtps::Bytes;
using test::rtps::data;
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
        out.insert(out.end(), second.begin() + RtpsDatagram::HEADER_BYTES, second.end());
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
