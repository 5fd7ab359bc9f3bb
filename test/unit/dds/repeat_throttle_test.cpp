// RepeatThrottle: which HEARTBEATs and ACKNACKs repeat one sent a moment ago, and are held back.
#include <gtest/gtest.h>

#include <chrono>

#include "gateway/dds/repeat_throttle.hpp"
#include "test/unit/wire/rtps_bytes.hpp"

namespace tgw::dds {
namespace {

using namespace std::chrono_literals;
using test::rtps::acknack;
using test::rtps::Bytes;
using test::rtps::data;
using test::rtps::heartbeat;
using test::rtps::info_dst;
using test::rtps::info_ts;
using test::rtps::message;
using test::rtps::statistics;

DatagramDestination to_port(std::uint32_t port) {
    eprosima::fastrtps::rtps::Locator_t locator;
    locator.kind = LOCATOR_KIND_UDPv4;
    locator.port = port;
    locator.address[15] = 2;
    return DatagramDestination{nullptr, {locator}};
}

class RepeatThrottleTest : public ::testing::Test {
  protected:
    bool admit(const Bytes& m, base::Duration at, const DatagramDestination& to = to_port(7661)) {
        return sut.admit(to, m.data(), m.size(), base::SteadyTime{} + at);
    }

    RepeatThrottle sut{1s};
    /// A lone HEARTBEAT as Fast DDS 2.9 answers an ACKNACK: to one reader, with the statistics trailer.
    Bytes answer = message({info_dst(0x33), heartbeat(0x11, 5, 1), statistics(0)});
};

TEST_F(RepeatThrottleTest, HoldsBackTheSameHeartbeatToTheSameReaderWithinTheInterval) {
    EXPECT_TRUE(admit(answer, 0ms));
    const Bytes again = message({info_dst(0x33), heartbeat(0x11, 5, 2), statistics(0)});  // only the count moved
    EXPECT_FALSE(admit(again, 70ms));
    EXPECT_FALSE(admit(again, 999ms));
    EXPECT_EQ(sut.suppressed(), 2u);
}

TEST_F(RepeatThrottleTest, LetsTheSameHeartbeatGoOnceTheIntervalHasPassed) {
    EXPECT_TRUE(admit(answer, 0ms));
    EXPECT_TRUE(admit(answer, 1000ms));
    EXPECT_FALSE(admit(answer, 1500ms)) << "the interval counts from the last one sent";
    EXPECT_TRUE(admit(answer, 2000ms));
}

TEST_F(RepeatThrottleTest, LetsAHeartbeatWithNewsGo) {
    EXPECT_TRUE(admit(answer, 0ms));
    EXPECT_TRUE(admit(message({info_dst(0x33), heartbeat(0x11, 6, 2), statistics(0)}), 10ms)) << "a new sample";
    EXPECT_TRUE(admit(message({info_dst(0x33), heartbeat(0x22, 5, 1), statistics(0)}), 20ms)) << "another writer";
    EXPECT_TRUE(admit(message({info_dst(0x44), heartbeat(0x11, 5, 1), statistics(0)}), 30ms)) << "another reader";
    EXPECT_TRUE(admit(answer, 40ms, to_port(7663))) << "another destination";
    EXPECT_EQ(sut.suppressed(), 0u);
}

// A reader matched to a writer that has not heard of it (a base camp that restarted, before the gateway's
// announcement reached it) sends it the same preemptive ACKNACK every 70 ms, only the count moving.
TEST_F(RepeatThrottleTest, HoldsBackTheSamePreemptiveAcknackWithinTheInterval) {
    const auto preemptive = [](std::uint8_t count) {
        return message({info_dst(0x44), acknack(0x22, 0x11, 0, 0, count), statistics(0)});
    };
    EXPECT_TRUE(admit(preemptive(1), 0ms));
    for (std::uint8_t count = 2; count <= 14; ++count) {
        EXPECT_FALSE(admit(preemptive(count), std::chrono::milliseconds(70 * (count - 1))));
    }
    EXPECT_TRUE(admit(preemptive(15), 1000ms));
    EXPECT_EQ(sut.suppressed(), 13u);
}

TEST_F(RepeatThrottleTest, LetsAnAcknackWithNewsGo) {
    EXPECT_TRUE(admit(message({info_dst(0x44), acknack(0x22, 0x11, 1, 0, 1)}), 0ms));
    EXPECT_TRUE(admit(message({info_dst(0x44), acknack(0x22, 0x11, 3, 0, 2)}), 10ms)) << "acknowledges more";
    EXPECT_TRUE(admit(message({info_dst(0x44), acknack(0x22, 0x11, 3, 8, 3)}), 20ms)) << "asks for a repair";
    EXPECT_TRUE(admit(message({info_dst(0x44), acknack(0x23, 0x11, 3, 8, 1)}), 30ms)) << "another reader";
    EXPECT_TRUE(admit(message({info_dst(0x44), acknack(0x22, 0x12, 3, 8, 1)}), 40ms)) << "another writer";
    EXPECT_TRUE(admit(message({info_dst(0x45), acknack(0x22, 0x11, 3, 8, 1)}), 50ms)) << "another participant";
    EXPECT_TRUE(admit(message({info_dst(0x44), heartbeat(0x22, 3, 1)}), 60ms)) << "a HEARTBEAT is no ACKNACK";
    EXPECT_EQ(sut.suppressed(), 0u);
}

/// An authentication handshake message as Fast DDS 2.9 sends it with DDS Security: a DATA of the participant
/// stateless message writer (entity id 00.02.01.c3), `sequence` its writer sequence number.
Bytes handshake(std::uint8_t sequence, std::uint8_t payload_fill = 0x42, std::uint8_t writer_kind = 0xc3) {
    Bytes body = {0, 0, 16, 0, 0x00, 0x02, 0x01, 0xc4, 0x00, 0x02, 0x01, writer_kind};
    const Bytes sn = {0, 0, 0, 0, sequence, 0, 0, 0};
    body.insert(body.end(), sn.begin(), sn.end());
    body.insert(body.end(), 5500, payload_fill);
    return test::rtps::submessage(0x15, 0x05, body);
}

// Fast DDS 2.9 resends a handshake message every 500 ms until it is answered, under a new sequence number.
TEST_F(RepeatThrottleTest, HoldsBackAResentHandshakeMessageForFiveSeconds) {
    EXPECT_TRUE(admit(message({info_dst(0x44), info_ts(1), handshake(1), statistics(0)}), 0ms));
    for (std::uint8_t resend = 2; resend <= 10; ++resend) {
        EXPECT_FALSE(admit(message({info_dst(0x44), info_ts(resend), handshake(resend), statistics(0)}),
                           std::chrono::milliseconds(500 * (resend - 1))));
    }
    EXPECT_TRUE(admit(message({info_dst(0x44), info_ts(11), handshake(11), statistics(0)}), 5000ms));
    EXPECT_EQ(sut.suppressed(), 9u);
}

TEST_F(RepeatThrottleTest, LetsANewHandshakeMessageAndOtherDataGo) {
    EXPECT_TRUE(admit(message({info_dst(0x44), info_ts(1), handshake(1)}), 0ms));
    EXPECT_TRUE(admit(message({info_dst(0x44), info_ts(2), handshake(2, 0x43)}), 10ms)) << "the next message";
    EXPECT_TRUE(admit(message({info_dst(0x45), info_ts(3), handshake(3)}), 20ms)) << "to another participant";
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(
            admit(message({info_dst(0x44), info_ts(4), handshake(4, 0x42, 0x02)}), std::chrono::milliseconds(30 + i)))
            << "a DATA of any other writer";
    }
    EXPECT_EQ(sut.suppressed(), 0u);
}

/// A participant's announcement as Fast DDS 2.9 sends it: a DATA(p) of the SPDP writer (entity id 00.01.00.c2) to
/// ENTITYID_UNKNOWN, its sequence number and parameter list (`fill` stands for its contents).
Bytes announcement(std::uint8_t fill = 0x50) {
    Bytes body = {0, 0, 16, 0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0xc2, 0, 0, 0, 0, 1, 0, 0, 0};
    body.insert(body.end(), 360, fill);
    return test::rtps::submessage(0x15, 0x05, body);
}

// Fast DDS 2.9 sends a periodic announcement to an initial peer and again to the participant discovered there.
TEST_F(RepeatThrottleTest, HoldsBackTheSameAnnouncementToTheSamePortAMomentLater) {
    const Bytes m = message({info_ts(1), announcement(), statistics(0)});
    EXPECT_TRUE(admit(m, 0ms));
    EXPECT_FALSE(admit(message({info_ts(2), announcement(), statistics(0)}), 1ms)) << "the copy";
    EXPECT_TRUE(admit(m, 1ms, to_port(7663))) << "another port";
    EXPECT_TRUE(admit(message({info_ts(3), announcement(0x51), statistics(0)}), 2ms)) << "news";
    // Its start-up repeats, 100 ms apart, and the next period's all go.
    EXPECT_TRUE(admit(m, 100ms));
    EXPECT_TRUE(admit(m, 200ms));
    EXPECT_TRUE(admit(m, 20s));
    EXPECT_EQ(sut.suppressed(), 1u);
}

TEST_F(RepeatThrottleTest, NeverHoldsBackAnythingButALoneHeartbeatOrAcknack) {
    const Bytes piggy_backed = message({info_dst(0x33), info_ts(1), data(40), heartbeat(0x11, 5, 1), statistics(0)});
    const Bytes two = message({info_dst(0x33), heartbeat(0x11, 5, 1), heartbeat(0x22, 5, 1)});
    const Bytes both = message({info_dst(0x33), acknack(), heartbeat(0x11, 5, 1)});
    const Bytes sample = message({info_ts(1), data(40)});
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(admit(piggy_backed, std::chrono::milliseconds(i)));
        EXPECT_TRUE(admit(two, std::chrono::milliseconds(i)));
        EXPECT_TRUE(admit(both, std::chrono::milliseconds(i)));
        EXPECT_TRUE(admit(sample, std::chrono::milliseconds(i)));
    }
    Bytes truncated = answer;
    truncated.resize(truncated.size() - 70);
    EXPECT_TRUE(admit(truncated, 0ms));
    EXPECT_TRUE(admit(truncated, 1ms));
    EXPECT_EQ(sut.suppressed(), 0u);
}

TEST_F(RepeatThrottleTest, RemembersManyWritersAndReadersApart) {
    for (int writer = 1; writer <= 200; ++writer) {
        for (std::uint8_t reader = 1; reader <= 10; ++reader) {
            const Bytes hb = message({info_dst(reader), heartbeat(static_cast<std::uint8_t>(writer), 5, 1)});
            ASSERT_TRUE(admit(hb, std::chrono::milliseconds(writer)));
            ASSERT_FALSE(admit(hb, std::chrono::milliseconds(writer + 500)));
        }
    }
    EXPECT_EQ(sut.suppressed(), 2000u);
}

}  // namespace
}  // namespace tgw::dds
