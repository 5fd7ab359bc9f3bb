// RtpsDatagram: which RTPS messages may share a datagram, and the bytes that result.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "test/unit/wire/rtps_bytes.hpp"
#include "wire/rtps_datagram.hpp"

namespace tgw::wire {
namespace {

using test::rtps::acknack;
using test::rtps::Bytes;
using test::rtps::data;
using test::rtps::data_frag;
using test::rtps::data_of;
using test::rtps::gap;
using test::rtps::heartbeat;
using test::rtps::info_dst;
using test::rtps::info_src;
using test::rtps::info_ts;
using test::rtps::message;
using test::rtps::PUBLICATIONS;
using test::rtps::signed_rtps;
using test::rtps::statistics;

constexpr std::size_t MAX_BYTES = 1472;

std::vector<std::uint8_t> contents(const RtpsDatagram& d) {
    return {d.data(), d.data() + d.size()};
}

bool append(RtpsDatagram& d, const Bytes& m) {
    return d.append(m.data(), m.size());
}

/// The submessages of `m`, without its header.
Bytes body(const Bytes& m) {
    return {m.begin() + RtpsDatagram::HEADER_BYTES, m.end()};
}

Bytes concat(std::initializer_list<Bytes> parts) {
    Bytes out;
    for (const Bytes& p : parts) {
        out.insert(out.end(), p.begin(), p.end());
    }
    return out;
}

class RtpsDatagramTest : public ::testing::Test {
  protected:
    RtpsDatagram sut{MAX_BYTES};
};

TEST_F(RtpsDatagramTest, TakesTheFirstMessageWhole) {
    const Bytes m = message({info_ts(1), data(40)});
    ASSERT_TRUE(append(sut, m));
    EXPECT_EQ(contents(sut), m);
    EXPECT_EQ(sut.messages(), 1u);
}

TEST_F(RtpsDatagramTest, AppendsLaterMessagesWithoutTheirHeader) {
    const Bytes first = message({info_ts(1), data(40)});
    const Bytes second = message({info_ts(2), data(44)});
    ASSERT_TRUE(append(sut, first));
    ASSERT_TRUE(append(sut, second));
    EXPECT_EQ(contents(sut), concat({first, body(second)}));
    EXPECT_EQ(sut.messages(), 2u);
}

TEST_F(RtpsDatagramTest, KeepsOnlyTheLastMessagesStatisticsSubmessage) {
    const Bytes first = message({info_ts(1), data(40), statistics(0x11)});
    const Bytes second = message({info_ts(2), data(40), statistics(0x22)});
    ASSERT_TRUE(append(sut, first));
    ASSERT_TRUE(append(sut, second));
    EXPECT_EQ(contents(sut), message({info_ts(1), data(40), info_ts(2), data(40), statistics(0x22)}));
}

TEST_F(RtpsDatagramTest, RefusesAMessageOfAnotherParticipant) {
    ASSERT_TRUE(append(sut, message({info_ts(1), data(40)})));
    EXPECT_FALSE(append(sut, message({info_ts(2), data(40)}, 0x02)));
    EXPECT_EQ(sut.messages(), 1u);
}

TEST_F(RtpsDatagramTest, RefusesAMessageThatWouldNotFit) {
    const Bytes big = message({info_ts(1), data(1000)});
    ASSERT_TRUE(append(sut, big));
    EXPECT_FALSE(append(sut, message({info_ts(2), data(600)})));
    EXPECT_TRUE(append(sut, message({info_ts(2), data(400)})));
}

TEST_F(RtpsDatagramTest, CountsTheStatisticsSubmessageItDropsWhenCheckingTheSize) {
    // 20 + 12 + 1308 + 60 = 1400 bytes, then a second of 20 + 12 + 44 + 60 - 20 = 116 bytes (1516 > 1472)
    // that fits because the first one's 60-byte statistics submessage goes.
    ASSERT_TRUE(append(sut, message({info_ts(1), data(1304), statistics(1)})));
    ASSERT_EQ(sut.size(), 1400u);
    EXPECT_TRUE(append(sut, message({info_ts(2), data(40), statistics(2)})));
    EXPECT_EQ(sut.size(), 1456u);
}

TEST_F(RtpsDatagramTest, AppendsAMessageThatSetsTheDestinationInForceAgain) {
    const Bytes first = message({info_dst(0x33), info_ts(1), data(40)});
    const Bytes second = message({info_dst(0x44), info_ts(2), data(40)});
    ASSERT_TRUE(append(sut, first));
    ASSERT_TRUE(append(sut, second));
    EXPECT_EQ(contents(sut), concat({first, body(second)}));
}

TEST_F(RtpsDatagramTest, LeavesOutAnInfoDstThatNamesTheParticipantInForce) {
    const Bytes first = message({info_dst(0x33), heartbeat()});
    const Bytes second = message({info_dst(0x33), info_ts(2), data(40), statistics(0)});
    ASSERT_TRUE(append(sut, first));
    ASSERT_TRUE(append(sut, second));
    EXPECT_EQ(contents(sut), concat({first, info_ts(2), data(40), statistics(0)}));
    // The destination in force is the last one named, here by the second message's own INFO_DST.
    const Bytes third = message({info_dst(0x44), heartbeat(), info_dst(0x33), heartbeat(0x12)});
    const Bytes fourth = message({info_dst(0x33), heartbeat(0x13)});
    RtpsDatagram other{MAX_BYTES};
    ASSERT_TRUE(append(other, third));
    ASSERT_TRUE(append(other, fourth));
    EXPECT_EQ(contents(other), concat({third, heartbeat(0x13)}));
}

TEST_F(RtpsDatagramTest, RefusesAMessageForEveryoneAfterOneForOneParticipant) {
    // Fast DDS keeps a destination in force for the rest of the datagram: the second sample would reach only
    // the first one's participant.
    ASSERT_TRUE(append(sut, message({info_dst(0x33), info_ts(1), data(40)})));
    EXPECT_FALSE(append(sut, message({info_ts(2), data(40)})));
}

TEST_F(RtpsDatagramTest, InvalidatesATimestampInForceBeforeAMessageWithoutOne) {
    const Bytes first = message({info_ts(1), data(40)});
    const Bytes second = message({data(40)});
    ASSERT_TRUE(append(sut, first));
    ASSERT_TRUE(append(sut, second));
    const Bytes invalidate = {0x09, 0x03, 0x00, 0x00};
    EXPECT_EQ(contents(sut), concat({first, invalidate, body(second)}));
}

TEST_F(RtpsDatagramTest, ClosesAfterASubmessageThatRunsToTheEndOfItsMessage) {
    Bytes last = data(40);
    last[2] = last[3] = 0;  // octetsToNextHeader 0: up to the end of the message
    ASSERT_TRUE(append(sut, message({info_ts(1), last})));
    EXPECT_FALSE(append(sut, message({info_ts(2), data(40)})));
}

TEST_F(RtpsDatagramTest, ClosesAfterAStateItDoesNotTrack) {
    ASSERT_TRUE(append(sut, message({info_src(), info_ts(1), data(40)})));
    EXPECT_FALSE(append(sut, message({info_ts(2), data(40)})));
}

TEST_F(RtpsDatagramTest, RefusesAMalformedMessageButSendsOneAlone) {
    Bytes truncated = message({info_ts(1), data(40)});
    truncated.resize(truncated.size() - 8);
    ASSERT_TRUE(append(sut, message({info_ts(1), data(40)})));
    EXPECT_FALSE(append(sut, truncated));

    sut.clear();
    EXPECT_TRUE(append(sut, truncated));
    EXPECT_FALSE(append(sut, message({info_ts(2), data(40)})));
}

TEST(RtpsHeartbeatBytes, CountsEveryHeartbeatSubmessageWithItsHeader) {
    const Bytes piggy_backed = message({info_dst(0x33), info_ts(1), data(40), heartbeat(), statistics(0)});
    EXPECT_EQ(RtpsDatagram::heartbeat_bytes(piggy_backed.data(), piggy_backed.size()), 32u);
    const Bytes two = message({heartbeat(), info_ts(1), data(40), heartbeat()});
    EXPECT_EQ(RtpsDatagram::heartbeat_bytes(two.data(), two.size()), 64u);
    const Bytes none = message({info_ts(1), data(40), statistics(0)});
    EXPECT_EQ(RtpsDatagram::heartbeat_bytes(none.data(), none.size()), 0u);
}

TEST(RtpsHeartbeatBytes, CountsNothingInAMalformedMessage) {
    Bytes truncated = message({info_ts(1), heartbeat()});
    truncated.resize(truncated.size() - 8);
    EXPECT_EQ(RtpsDatagram::heartbeat_bytes(truncated.data(), truncated.size()), 0u);
}

TEST(RtpsStatisticsTrailer, IsTheLastSubmessageWhenItIsTheStatisticsOne) {
    const Bytes with = message({info_dst(0x33), info_ts(1), data(40), statistics(0)});
    EXPECT_EQ(RtpsDatagram::statistics_trailer_bytes(with.data(), with.size()), 60u);
    // What is left is the message without it, still well formed.
    const Bytes without = message({info_dst(0x33), info_ts(1), data(40)});
    EXPECT_TRUE(std::equal(without.begin(), without.end(), with.begin()));
    EXPECT_EQ(RtpsDatagram::statistics_trailer_bytes(without.data(), without.size()), 0u);
    // An INFO_SRC makes a message unmergeable, not its trailer any less a trailer.
    const Bytes sourced = message({info_src(), info_ts(1), data(40), statistics(0)});
    EXPECT_EQ(RtpsDatagram::statistics_trailer_bytes(sourced.data(), sourced.size()), 60u);
}

TEST(RtpsStatisticsTrailer, IsNothingWhenTheStatisticsSubmessageIsNotLastOrTheMessageIsMalformed) {
    const Bytes middle = message({info_ts(1), statistics(0), data(40)});
    EXPECT_EQ(RtpsDatagram::statistics_trailer_bytes(middle.data(), middle.size()), 0u);
    Bytes truncated = message({info_ts(1), data(40), statistics(0)});
    truncated.resize(truncated.size() - 8);
    EXPECT_EQ(RtpsDatagram::statistics_trailer_bytes(truncated.data(), truncated.size()), 0u);
    Bytes cyclone = message({info_ts(1), data(40), statistics(0)});
    cyclone[6] = 0x01;
    cyclone[7] = 0x10;
    EXPECT_EQ(RtpsDatagram::statistics_trailer_bytes(cyclone.data(), cyclone.size()), 0u);
}

TEST(RtpsLeadingDestination, IsTheInfoDstAMessageToOneParticipantStartsWith) {
    const Bytes to_one = message({info_dst(0x33), info_ts(1), data(40), statistics(0)});
    ASSERT_EQ(RtpsDatagram::leading_destination_bytes(to_one.data(), to_one.size()), 16u);
    // What is left reads as a message of its own: the header, then the submessages after the INFO_DST.
    Bytes without(to_one.begin(), to_one.begin() + RtpsDatagram::HEADER_BYTES);
    without.insert(without.end(), to_one.begin() + RtpsDatagram::HEADER_BYTES + 16, to_one.end());
    EXPECT_EQ(without, message({info_ts(1), data(40), statistics(0)}));
    EXPECT_EQ(RtpsDatagram::statistics_trailer_bytes(without.data(), without.size()), 60u);
}

TEST(RtpsLeadingDestination, IsNothingUnlessOneParticipantIsNamedFirstInAPlainWellFormedMessage) {
    const auto cut = [](const Bytes& m) { return RtpsDatagram::leading_destination_bytes(m.data(), m.size()); };
    EXPECT_EQ(cut(message({info_ts(1), data(40)})), 0u);                                // names nobody
    EXPECT_EQ(cut(message({info_dst(0), info_ts(1), data(40)})), 0u);                   // GUIDPREFIX_UNKNOWN
    EXPECT_EQ(cut(message({info_ts(1), info_dst(0x33), data(40)})), 0u);                // not first
    EXPECT_EQ(cut(message({info_dst(0x33), data(40), info_dst(0x44), data(40)})), 0u);  // two participants
    EXPECT_EQ(cut(message(signed_rtps({info_dst(0x33), info_ts(1), data(40)}))), 0u);   // signed as it is
    Bytes truncated = message({info_dst(0x33), info_ts(1), data(40)});
    truncated.resize(truncated.size() - 8);
    EXPECT_EQ(cut(truncated), 0u);
}

TEST(RtpsLoneSampleTimestamp, IsTheInfoTsOfAMessageThatCarriesOneSample) {
    const auto stamp = [](const Bytes& m) { return RtpsDatagram::strippable(m.data(), m.size()).timestamp_bytes; };
    EXPECT_EQ(stamp(message({info_ts(1), data(40)})), 12u);
    EXPECT_EQ(stamp(message({info_ts(1), data(40), statistics(0)})), 12u);
    const Bytes to_one = message({info_dst(0x33), info_ts(1), data(40), statistics(0)});
    const RtpsDatagram::Strippable sut = RtpsDatagram::strippable(to_one.data(), to_one.size());
    ASSERT_EQ(sut.destination_bytes, 16u);
    ASSERT_EQ(sut.timestamp_bytes, 12u);
    // Both come right after the header: cut together, what is left is the sample's DATA alone.
    Bytes without(to_one.begin(), to_one.begin() + RtpsDatagram::HEADER_BYTES);
    without.insert(without.end(), to_one.begin() + RtpsDatagram::HEADER_BYTES + 16 + 12, to_one.end());
    EXPECT_EQ(without, message({data(40), statistics(0)}));
}

TEST(RtpsLoneSampleTimestamp, IsNothingUnlessTheMessageIsOneStampedSampleAndPlain) {
    const auto stamp = [](const Bytes& m) { return RtpsDatagram::strippable(m.data(), m.size()).timestamp_bytes; };
    const Bytes invalidate = {0x09, 0x03, 0x00, 0x00};
    EXPECT_EQ(stamp(message({data(40)})), 0u);                                    // no timestamp
    EXPECT_EQ(stamp(message({invalidate, data(40)})), 0u);                        // no time in it
    EXPECT_EQ(stamp(message({info_ts(1), data(40), info_ts(2), data(40)})), 0u);  // two samples
    EXPECT_EQ(stamp(message({info_ts(1), data(40), data(40)})), 0u);              // two under one stamp
    EXPECT_EQ(stamp(message({info_ts(1), data(40), heartbeat()})), 0u);           // a HEARTBEAT after it
    EXPECT_EQ(stamp(message({heartbeat(), info_ts(1), data(40)})), 0u);           // not right after the header
    EXPECT_EQ(stamp(message({info_ts(1), info_dst(0x33), data(40)})), 0u);        // INFO_DST between
    EXPECT_EQ(stamp(message({info_ts(1), heartbeat()})), 0u);                     // no sample
    EXPECT_EQ(stamp(message(signed_rtps({info_ts(1), data(40)}))), 0u);           // signed as it is
    Bytes truncated = message({info_ts(1), data(40)});
    truncated.resize(truncated.size() - 8);
    EXPECT_EQ(stamp(truncated), 0u);
}

TEST(RtpsUserSample, IsADataOrDataFragOfAnApplicationsWriter) {
    const auto carries = [](const Bytes& m) {
        return RtpsDatagram::strippable(m.data(), m.size()).carries_user_sample;
    };
    constexpr std::array<std::uint8_t, 4> USER_WRITER{0x00, 0x00, 0x01, 0x03};
    constexpr std::array<std::uint8_t, 4> SPDP_WRITER{0x00, 0x01, 0x00, 0xc2};
    EXPECT_TRUE(carries(message({info_ts(1), data_of(USER_WRITER, 1), statistics(0)})));
    EXPECT_TRUE(carries(message({info_dst(0x33), data_frag(USER_WRITER, 1, 2), heartbeat(), statistics(0)})));
    EXPECT_TRUE(carries(message({heartbeat(), info_ts(1), data_of(USER_WRITER, 2)})));
    // What a base camp's channel meter can do without: control alone, and discovery.
    EXPECT_FALSE(carries(message({info_dst(0x33), heartbeat(), statistics(0)})));
    EXPECT_FALSE(carries(message({info_dst(0x33), acknack(), statistics(0)})));
    EXPECT_FALSE(carries(message({info_dst(0x33), gap(USER_WRITER, 3), statistics(0)})));
    EXPECT_FALSE(carries(message({info_ts(1), data_of(SPDP_WRITER, 1), statistics(0)})));
    EXPECT_FALSE(carries(message({info_ts(1), data_of(PUBLICATIONS, 1), heartbeat(), statistics(0)})));
    // Protected, a sample cannot be told from the rest.
    EXPECT_TRUE(carries(message(signed_rtps({heartbeat()}))));
}

TEST(RtpsUserControl, IsAWritersHeartbeatsAndGapsAlone) {
    const auto control = [](const Bytes& m) { return RtpsDatagram::user_control_only(m.data(), m.size()); };
    constexpr std::array<std::uint8_t, 4> USER_WRITER{0x00, 0x00, 0x01, 0x03};
    EXPECT_TRUE(control(message({info_dst(0x33), heartbeat()})));
    EXPECT_TRUE(control(message({info_dst(0x33), heartbeat(), statistics(0)})));
    EXPECT_TRUE(control(message({info_dst(0x33), gap(USER_WRITER, 3), heartbeat()})));
    EXPECT_FALSE(control(message({info_dst(0x33)})));                                     // nothing to carry
    EXPECT_FALSE(control(message({info_dst(0x33), info_ts(1), data(40), heartbeat()})));  // a sample
    EXPECT_FALSE(control(message({info_dst(0x33), acknack()})));                          // a reader's
    EXPECT_FALSE(control(message({info_dst(0x33), heartbeat(0xc2)})));                    // discovery's writer
    EXPECT_FALSE(control(message({info_src(), heartbeat()})));                            // state not tracked
    EXPECT_FALSE(control(message(signed_rtps({heartbeat()}))));
}

TEST_F(RtpsDatagramTest, SendsAMessageProtectedAsAWholeAlone) {
    // A receiver decodes the protected message and reads nothing after its SRTPS_POSTFIX.
    const Bytes secured = message(signed_rtps({info_ts(1), data(40)}));
    ASSERT_TRUE(append(sut, secured));
    EXPECT_FALSE(append(sut, message(signed_rtps({info_ts(2), data(40)}))));
    EXPECT_FALSE(append(sut, message({info_ts(2), data(40)})));
    EXPECT_EQ(contents(sut), secured);
}

TEST_F(RtpsDatagramTest, RefusesAMessageProtectedAsAWholeAfterAPlainOne) {
    ASSERT_TRUE(append(sut, message({info_ts(1), data(40)})));
    EXPECT_FALSE(append(sut, message(signed_rtps({info_ts(2), data(40)}))));
}

TEST_F(RtpsDatagramTest, KeepsTheStatisticsSubmessageAfterAProtectedMessage) {
    // Fast DDS adds it after the protection: stripping it leaves the protected message whole.
    const Bytes secured = message(signed_rtps({info_ts(1), data(40)}));
    Bytes with_trailer = secured;
    const Bytes trailer = statistics(7);
    with_trailer.insert(with_trailer.end(), trailer.begin(), trailer.end());
    EXPECT_EQ(RtpsDatagram::statistics_trailer_bytes(with_trailer.data(), with_trailer.size()), trailer.size());
}

TEST_F(RtpsDatagramTest, CountsProtectedSubmessagesPastASamplesOwnAsItsHeartbeat) {
    // Shaped as a capture of a secured reliable writer's sample: INFO_DST in clear, then INFO_TS, DATA and the
    // piggy-backed HEARTBEAT each as SEC_PREFIX, SEC_BODY, SEC_POSTFIX (24 + 40 + 24 bytes for the HEARTBEAT).
    const auto protect = [](std::size_t body_bytes) {
        return std::vector<Bytes>{test::rtps::submessage(0x31, 0x01, Bytes(20, 1)),
                                  test::rtps::submessage(0x30, 0x01, Bytes(body_bytes, 2)),
                                  test::rtps::submessage(0x32, 0x01, Bytes(20, 3))};
    };
    std::vector<Bytes> alone{info_dst(0x33)};
    for (std::size_t body : {16u, 136u}) {
        const auto group = protect(body);
        alone.insert(alone.end(), group.begin(), group.end());
    }
    std::vector<Bytes> with_heartbeat = alone;
    const auto heartbeat_group = protect(36);
    with_heartbeat.insert(with_heartbeat.end(), heartbeat_group.begin(), heartbeat_group.end());
    const auto wrap = [](const std::vector<Bytes>& inner) {
        std::vector<Bytes> out{test::rtps::submessage(0x33, 0x01, Bytes(20, 0x3c)),
                               test::rtps::submessage(0x0c, 0x01, Bytes(20, 7))};
        out.insert(out.end(), inner.begin(), inner.end());
        out.push_back(test::rtps::submessage(0x34, 0x01, Bytes(20, 0x4d)));
        out.push_back(statistics(1));
        return out;
    };
    const Bytes sample = message(wrap(alone));
    const Bytes sample_and_heartbeat = message(wrap(with_heartbeat));
    EXPECT_EQ(RtpsDatagram::heartbeat_bytes(sample.data(), sample.size()), 0u);
    EXPECT_EQ(RtpsDatagram::heartbeat_bytes(sample_and_heartbeat.data(), sample_and_heartbeat.size()), 88u);
}

TEST_F(RtpsDatagramTest, PadsADatagramWhoseEndAFastDdsTransportWouldTakeForStatistics) {
    // A DATA whose payload has the statistics id 60 bytes before the end of the message.
    Bytes m = message({info_ts(1), data(80)});
    EXPECT_EQ(RtpsDatagram::padding_against_statistics_fill(m.data(), m.size()), 0u);
    m[m.size() - RtpsDatagram::STATISTICS_BYTES] = 0x80;
    EXPECT_EQ(RtpsDatagram::padding_against_statistics_fill(m.data(), m.size()), 4u);
    // ... and 4 bytes on too: one PAD more.
    m[m.size() - RtpsDatagram::STATISTICS_BYTES + 4] = 0x80;
    EXPECT_EQ(RtpsDatagram::padding_against_statistics_fill(m.data(), m.size()), 8u);
}

TEST_F(RtpsDatagramTest, LeavesAMessageThatEndsWithItsStatisticsAsItIs) {
    const Bytes m = message({info_ts(1), data(40), statistics(0)});
    EXPECT_EQ(RtpsDatagram::padding_against_statistics_fill(m.data(), m.size()), 0u);
}

TEST_F(RtpsDatagramTest, ClearStartsOver) {
    ASSERT_TRUE(append(sut, message({info_dst(0x33), info_ts(1), data(40)})));
    sut.clear();
    EXPECT_TRUE(sut.empty());
    ASSERT_TRUE(append(sut, message({info_ts(1), data(40)})));
    EXPECT_TRUE(append(sut, message({info_ts(2), data(40)})));
}

}  // namespace
}  // namespace tgw::wire
