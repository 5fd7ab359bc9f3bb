// ChannelMeter: what it counts of the datagrams the relay's WAN transport receives.
#include "basecamp/channel/channel_meter.hpp"

#include <gtest/gtest.h>

#include <optional>

#include "test/fakes/fake_clock.hpp"
#include "test/unit/wire/rtps_bytes.hpp"
#include "wire/rtps_datagram.hpp"

namespace tgw::basecamp {
namespace {

using namespace std::chrono_literals;
using test::rtps::Bytes;
using test::rtps::data;
using test::rtps::info_ts;
using test::rtps::message;
using test::rtps::statistics;

/// A 40-byte sample's datagram from participant `sender`, its `sequence`-th to `port`, sent `age` before `now`.
Bytes datagram(std::uint8_t sender, std::uint64_t sequence, base::WallTime now, base::Duration age = 50ms,
               std::uint32_t port = 7411) {
    Bytes m = message({info_ts(1), data(40), statistics(0)}, sender);
    const auto sent = std::chrono::duration_cast<std::chrono::seconds>((now - age).time_since_epoch());
    // The stamp's half second: the sender's clock reads `now - age` rounded down to the second, plus 0.5 s.
    test::rtps::stamp(m, static_cast<std::uint32_t>(sent.count()), sequence, port);
    return m;
}

/// The GUID prefix test::rtps::message() gives participant `sender`.
ParticipantPrefix prefix_of(std::uint8_t sender) {
    ParticipantPrefix prefix;
    prefix.fill(sender);
    return prefix;
}

/// An IPv4 address as Fast DDS's locators hold it.
SourceAddress ipv4(std::uint8_t last) {
    return SourceAddress{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 10, 0, 0, last};
}

/// Participants 1 and 2 are gateways (they sent a status).
class ChannelMeterTest : public ::testing::Test {
  protected:
    ChannelMeterTest() {
        meter_.gateway(prefix_of(1));
        meter_.gateway(prefix_of(2));
    }

    /// From `from`: by default the address of the sender the test participant `bytes` names (10.0.0.N).
    void receive(const Bytes& bytes, std::optional<SourceAddress> from = std::nullopt) {
        const std::optional<ParticipantPrefix> sender = wire::RtpsDatagram::sender(bytes.data(), bytes.size());
        meter_.datagram(bytes.data(), bytes.size(), from ? *from : ipv4(sender ? (*sender)[0] : 0));
    }

    test::FakeClock clock_;
    ChannelMeter meter_{60'000, clock_};
};

TEST_F(ChannelMeterTest, CountsEveryDatagramAndReadsTheStampsOfThoseThatHaveOne) {
    const Bytes stamped = datagram(1, 1, clock_.wall_now());
    receive(stamped);
    const Bytes compact = message({info_ts(1), data(40)}, 2);  // a compact-mode gateway strips the statistics
    receive(compact);
    const ChannelReading r = meter_.reading();
    EXPECT_EQ(r.datagrams, 2u);
    EXPECT_EQ(r.stamped_datagrams, 1u);
    EXPECT_EQ(r.lost_datagrams, 0u);

    // What the channel carried: each datagram with its Ethernet, IP and UDP headers.
    meter_.measure(0, 0);
    clock_.advance(1s);
    receive(stamped);
    receive(compact);
    meter_.measure(0, 0);
    EXPECT_NEAR(*meter_.reading().delivered_bps, 8.0 * (stamped.size() + compact.size() + 2 * 42), 1);
    EXPECT_TRUE(meter_.reading().queueing.has_value()) << "the stamped datagram's delay";
}

// Commands the camp sends on a half-duplex channel took its air as the robots' datagrams did.
TEST_F(ChannelMeterTest, WhatTheCampSentOnTheChannelCountsAsDelivered) {
    meter_.measure(0, 0);
    clock_.advance(1s);
    const Bytes stamped = datagram(1, 1, clock_.wall_now());
    receive(stamped);
    meter_.camp_sent(2'420);
    meter_.measure(0, 0);
    EXPECT_NEAR(*meter_.reading().delivered_bps, 8.0 * (stamped.size() + 42 + 2'420), 1);
    EXPECT_EQ(meter_.reading().datagrams, 1u) << "no datagram of its own received";
}

TEST_F(ChannelMeterTest, GapsInASendersSequenceToOneDestinationAreLostDatagrams) {
    const base::WallTime now = clock_.wall_now();
    for (std::uint64_t sequence : {1, 2, 5, 6}) {
        receive(datagram(1, sequence, now));
    }
    EXPECT_EQ(meter_.reading().lost_datagrams, 2u) << "3 and 4";
    receive(datagram(1, 1, now, 50ms, 7413));  // its first to another of the relay's locators: a sequence of its own
    receive(datagram(2, 9, now));              // another sender's first: where it starts is no loss
    receive(datagram(1, 4, now));              // late, behind 6: still counted lost
    EXPECT_EQ(meter_.reading().lost_datagrams, 2u);
    receive(datagram(2, 12, now));
    EXPECT_EQ(meter_.reading().lost_datagrams, 4u);
}

TEST_F(ChannelMeterTest, LostDatagramsCutTheChannel) {
    meter_.measure(0, 0);
    const base::WallTime now = clock_.wall_now();
    for (std::uint64_t sequence = 1; sequence <= 100; sequence += 2) {  // every other datagram lost
        receive(datagram(1, sequence, now));
    }
    clock_.advance(1s);
    EXPECT_LT(meter_.measure(0, 54'000).channel_bps, 60'000);
    EXPECT_EQ(meter_.reading().verdict, core::ChannelVerdict::losing);
}

// A participant beside the relay (the discovery server, a camp tool on the WAN domain) sends datagrams that never
// crossed the channel: they tell neither its rate nor its queue.
TEST_F(ChannelMeterTest, OnlyTheGatewaysDatagramsCount) {
    meter_.measure(0, 0);
    for (int second = 0; second < 3; ++second) {
        const base::WallTime now = clock_.wall_now();
        for (std::uint64_t i = 1; i <= 10; ++i) {
            receive(datagram(1, 10 * second + i, now, second == 0 ? 50ms : 1050ms));  // rover1: its queue grows
            receive(datagram(7, 10 * second + i, now, 0ms));                          // the server: never waits
        }
        receive(Bytes{'n', 'o', 't', ' ', 'R', 'T', 'P', 'S'});
        clock_.advance(1s);
        meter_.measure(0, 54'000);
    }
    const ChannelReading r = meter_.reading();
    EXPECT_EQ(r.datagrams, 30u) << "rover1's alone";
    ASSERT_TRUE(r.queueing.has_value());
    EXPECT_GT(*r.queueing, 700ms);
    EXPECT_EQ(r.verdict, core::ChannelVerdict::queueing);

    meter_.gateway(prefix_of(7));  // it turns out to be a gateway after all: from now on it counts
    receive(datagram(7, 31, clock_.wall_now(), 0ms));
    EXPECT_EQ(meter_.reading().datagrams, 31u);
}

// rover3's gateway restarted: its new participant's discovery crossed the channel as a burst before its first
// status, and uncounted it made the channel look half used while it queued (a cut to 31,493 bit/s of 60,000, the
// fleet's hazards late for 3 s).
TEST_F(ChannelMeterTest, ANewParticipantOnAGatewaysHostCountsFromItsFirstDatagram) {
    receive(datagram(1, 1, clock_.wall_now()));           // rover1's gateway, from 10.0.0.1
    receive(datagram(9, 1, clock_.wall_now()), ipv4(1));  // its host's new participant
    receive(datagram(8, 1, clock_.wall_now()));           // from 10.0.0.8: no gateway's host
    EXPECT_EQ(meter_.reading().datagrams, 2u);
}

}  // namespace
}  // namespace tgw::basecamp
