#include <gtest/gtest.h>

#include <sstream>

#include "GatewayStatus.h"
#include "KeyedReading.h"
#include "PaperWorkload.h"
#include "ReceiverReport.h"
#include "RosString.h"

#include "test/unit/types/cdr_test_payloads.hpp"
#include "types/cdr_decoder.hpp"

namespace tgw::test {
namespace {

using eprosima::fastcdr::Cdr;
using types::CdrDecodeResult;
using types::DecodedValue;

constexpr std::uint16_t CDR_LE = 0x0001;
constexpr std::uint16_t CDR2_BE = 0x0006;
constexpr std::uint16_t CDR2_LE = 0x0007;
constexpr std::uint16_t D_CDR2_LE = 0x0009;

class CdrDecoderTest : public ::testing::Test {
  protected:
    void SetUp() override { types_.add_project_types(); }

    void add_idl(const std::string& text) {
        std::istringstream in(text);
        types_.add_idl(in, "test.idl");
        types_.check_references();
    }

    CdrDecodeResult decode(const std::vector<std::uint8_t>& payload, const std::string& type) const {
        return types::decode_cdr(payload.data(), payload.size(), type, types_);
    }

    /// Decodes and fails the test with the decoder's error when there is no value.
    DecodedValue decoded(const std::vector<std::uint8_t>& payload, const std::string& type) const {
        CdrDecodeResult result = decode(payload, type);
        EXPECT_TRUE(result.value.has_value()) << result.error;
        return result.value.value_or(DecodedValue{});
    }

    types::TypeLibrary types_;
};

idl::GatewayStatus example_status() {
    idl::GatewayStatus status;
    status.gateway_prefix({1, 15, 2, 3, 4, 5, 6, 7, 8, 9, 10, 255});
    status.robot_name("rover_1");
    status.sent_ns(1'764'000'000'123'456'789ULL);
    status.sensed_rate_bps(20'000.5);
    status.sensor("qdisc:veth0");
    status.sensor_detail("tbf rate 20kbit");
    status.status_period_s(1.0);
    status.budget_bps(19'000.25);
    status.unscheduled_wire_bytes(4096);
    status.log_samples(17);
    status.matched_readers(-1);
    for (int i = 0; i < 2; ++i) {
        idl::TopicStatus topic;
        topic.name(i == 0 ? "telemetry/A" : "telemetry/B");
        topic.ttl_ms(1000u * static_cast<unsigned>(i + 1));
        topic.queued_samples(3u + static_cast<unsigned>(i));
        topic.queued_bytes(123'456'789'012ULL);
        topic.received(500u + static_cast<unsigned>(i));
        topic.forwarded(490);
        topic.forwarded_wire_bytes(77'000);
        topic.expired(1);
        topic.doomed(2);
        topic.evicted(3);
        topic.oversize(4);
        topic.shutdown(5);
        topic.write_failed(6);
        topic.no_reader(8);
        topic.matched_readers(i);
        status.topics().push_back(topic);
    }
    return status;
}

class CdrDecoderByteOrderTest : public CdrDecoderTest, public ::testing::WithParamInterface<Cdr::Endianness> {};

TEST_P(CdrDecoderByteOrderTest, DecodesEveryFieldOfAGatewayStatusAsItsGeneratedTypeSerializedIt) {
    const std::vector<std::uint8_t> payload = fastcdr_payload(example_status(), GetParam());
    ASSERT_EQ(payload[1], GetParam() == Cdr::LITTLE_ENDIANNESS ? 0x01 : 0x00);  // CDR_LE / CDR_BE
    const DecodedValue sut = decoded(payload, "tgw::idl::GatewayStatus");

    const DecodedValue& prefix = member(sut, "gateway_prefix");
    ASSERT_EQ(prefix.kind, DecodedValue::Kind::list);
    ASSERT_EQ(prefix.items.size(), 12u);
    EXPECT_EQ(prefix.items[1].unsigned_integer, 15u);
    EXPECT_EQ(prefix.items[11].unsigned_integer, 255u);
    EXPECT_EQ(member(sut, "robot_name").text, "rover_1");
    EXPECT_EQ(member(sut, "sent_ns").unsigned_integer, 1'764'000'000'123'456'789ULL);
    EXPECT_EQ(member(sut, "sensed_rate_bps").real, 20'000.5);
    EXPECT_EQ(member(sut, "sensor").text, "qdisc:veth0");
    EXPECT_EQ(member(sut, "sensor_detail").text, "tbf rate 20kbit");
    EXPECT_EQ(member(sut, "status_period_s").real, 1.0);
    EXPECT_EQ(member(sut, "budget_bps").real, 19'000.25);
    EXPECT_EQ(member(sut, "unscheduled_wire_bytes").unsigned_integer, 4096u);
    EXPECT_EQ(member(sut, "log_samples").unsigned_integer, 17u);
    EXPECT_EQ(member(sut, "matched_readers").kind, DecodedValue::Kind::signed_integer);
    EXPECT_EQ(member(sut, "matched_readers").signed_integer, -1);

    const DecodedValue& topics = member(sut, "topics");
    ASSERT_EQ(topics.items.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        const DecodedValue& topic = topics.items[i];
        EXPECT_EQ(member(topic, "name").text, i == 0 ? "telemetry/A" : "telemetry/B");
        EXPECT_EQ(member(topic, "ttl_ms").unsigned_integer, 1000u * (i + 1));
        EXPECT_EQ(member(topic, "queued_samples").unsigned_integer, 3u + i);
        EXPECT_EQ(member(topic, "queued_bytes").unsigned_integer, 123'456'789'012ULL);
        EXPECT_EQ(member(topic, "received").unsigned_integer, 500u + i);
        EXPECT_EQ(member(topic, "forwarded").unsigned_integer, 490u);
        EXPECT_EQ(member(topic, "forwarded_wire_bytes").unsigned_integer, 77'000u);
        EXPECT_EQ(member(topic, "expired").unsigned_integer, 1u);
        EXPECT_EQ(member(topic, "doomed").unsigned_integer, 2u);
        EXPECT_EQ(member(topic, "evicted").unsigned_integer, 3u);
        EXPECT_EQ(member(topic, "oversize").unsigned_integer, 4u);
        EXPECT_EQ(member(topic, "shutdown").unsigned_integer, 5u);
        EXPECT_EQ(member(topic, "write_failed").unsigned_integer, 6u);
        EXPECT_EQ(member(topic, "no_reader").unsigned_integer, 8u);
        EXPECT_EQ(member(topic, "matched_readers").signed_integer, static_cast<std::int64_t>(i));
    }
}

TEST_P(CdrDecoderByteOrderTest, DecodesTheOtherProjectTypesAsTheirGeneratedTypesSerializedThem) {
    idl::KeyedReading reading;
    reading.sensor_id(7);
    reading.value(-21.25);
    reading.label("north");
    const DecodedValue keyed = decoded(fastcdr_payload(reading, GetParam()), "tgw::idl::KeyedReading");
    EXPECT_EQ(member(keyed, "sensor_id").unsigned_integer, 7u);
    EXPECT_EQ(member(keyed, "value").real, -21.25);
    EXPECT_EQ(member(keyed, "label").text, "north");

    idl::PaperMessage message;
    message.generated_ns(1'764'000'000'000'000'001ULL);
    message.sequence_number(42);
    message.data({0, 1, 2, 250});
    const DecodedValue paper = decoded(fastcdr_payload(message, GetParam()), "tgw::idl::PaperMessage");
    EXPECT_EQ(member(paper, "generated_ns").unsigned_integer, 1'764'000'000'000'000'001ULL);
    EXPECT_EQ(member(paper, "sequence_number").unsigned_integer, 42u);
    ASSERT_EQ(member(paper, "data").items.size(), 4u);
    EXPECT_EQ(member(paper, "data").items[3].unsigned_integer, 250u);

    idl::ReceiverReport report;
    report.gateway_prefix({9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 1});
    report.received_samples(10);
    report.received_bytes(2000);
    report.lost_samples(3);
    report.sent_ns(5);
    const DecodedValue received = decoded(fastcdr_payload(report, GetParam()), "tgw::idl::ReceiverReport");
    EXPECT_EQ(member(received, "gateway_prefix").items[11].unsigned_integer, 1u);
    EXPECT_EQ(member(received, "received_samples").unsigned_integer, 10u);
    EXPECT_EQ(member(received, "received_bytes").unsigned_integer, 2000u);
    EXPECT_EQ(member(received, "lost_samples").unsigned_integer, 3u);
    EXPECT_EQ(member(received, "sent_ns").unsigned_integer, 5u);

    std_msgs::msg::dds_::String_ chatter;
    chatter.data("Hello World: 5");
    const DecodedValue ros = decoded(fastcdr_payload(chatter, GetParam()), "std_msgs::msg::dds_::String_");
    EXPECT_EQ(member(ros, "data").text, "Hello World: 5");
}

INSTANTIATE_TEST_SUITE_P(BothByteOrders, CdrDecoderByteOrderTest,
                         ::testing::Values(Cdr::BIG_ENDIANNESS, Cdr::LITTLE_ENDIANNESS), [](const auto& info) {
                             return info.param == Cdr::BIG_ENDIANNESS ? "BigEndian" : "LittleEndian";
                         });

TEST_F(CdrDecoderTest, GivesAnErrorForEveryTruncationOfAPayloadNeverAValue) {
    const std::vector<std::uint8_t> payload = fastcdr_payload(example_status(), Cdr::LITTLE_ENDIANNESS);
    for (std::size_t size = 0; size < payload.size(); ++size) {
        const std::vector<std::uint8_t> cut(payload.begin(), payload.begin() + static_cast<std::ptrdiff_t>(size));
        const CdrDecodeResult sut = decode(cut, "tgw::idl::GatewayStatus");
        EXPECT_FALSE(sut.value.has_value()) << "cut to " << size << " bytes";
        EXPECT_FALSE(sut.error.empty()) << "cut to " << size << " bytes";
    }
}

TEST_F(CdrDecoderTest, SaysWhichMemberRanOutOfBytes) {
    add_idl("struct Inner { string name; }; struct Outer { sequence<Inner> items; };");
    CdrWriter payload(CDR_LE, true, false);
    payload.u32(2).str("first").u32(40);  // the second name claims 40 bytes
    const CdrDecodeResult sut = decode(payload.bytes(), "Outer");
    ASSERT_FALSE(sut.value.has_value());
    EXPECT_EQ(sut.error, "items[1].name: needs 40 bytes at offset 24, 0 are left");
}

TEST_F(CdrDecoderTest, AlignsEightByteMembersToEightInXcdr1AndToFourInXcdr2) {
    add_idl("@final struct Pair { uint32 a; uint64 b; };");
    CdrWriter xcdr1(CDR_LE, true, false);
    xcdr1.u32(1).u64(0x1122334455667788ULL);
    ASSERT_EQ(xcdr1.bytes().size(), 4u + 16u);  // 4 bytes of padding before b
    EXPECT_EQ(member(decoded(xcdr1.bytes(), "Pair"), "b").unsigned_integer, 0x1122334455667788ULL);

    CdrWriter xcdr2(CDR2_LE, true, true);
    xcdr2.u32(1).u64(0x1122334455667788ULL);
    ASSERT_EQ(xcdr2.bytes().size(), 4u + 12u);  // none
    EXPECT_EQ(member(decoded(xcdr2.bytes(), "Pair"), "b").unsigned_integer, 0x1122334455667788ULL);
}

TEST_F(CdrDecoderTest, ReadsAnAppendableStructInXcdr2ThroughItsDheaderInBothByteOrders) {
    add_idl(R"(
        @appendable struct Reading {
            uint8 flag;
            uint64 stamp;
            sequence<string> names;
            sequence<int16> small;
            double value;
        };)");
    for (const bool little : {true, false}) {
        CdrWriter payload(little ? CDR2_LE : CDR2_BE, little, true);
        const std::size_t outer = payload.begin_dheader();
        payload.u8(1).u64(99);
        const std::size_t names = payload.begin_dheader();  // strings are not primitive: a DHEADER
        payload.u32(2).str("a").str("bc").end_dheader(names);
        payload.u32(2).u16(7).u16(0xfffe);  // int16 is: none
        payload.f64(2.5).end_dheader(outer);
        const DecodedValue sut = decoded(payload.bytes(), "Reading");
        EXPECT_TRUE(member(sut, "flag").unsigned_integer == 1u);
        EXPECT_EQ(member(sut, "stamp").unsigned_integer, 99u);
        ASSERT_EQ(member(sut, "names").items.size(), 2u);
        EXPECT_EQ(member(sut, "names").items[1].text, "bc");
        ASSERT_EQ(member(sut, "small").items.size(), 2u);
        EXPECT_EQ(member(sut, "small").items[1].signed_integer, -2);
        EXPECT_EQ(member(sut, "value").real, 2.5);
    }
}

TEST_F(CdrDecoderTest, SkipsWhatANewerAppendableVersionAddedAndLeavesOutWhatAnOlderOneLacked) {
    add_idl("@appendable struct Inner { uint32 a; uint32 b; }; @final struct Outer { Inner inner; uint32 after; };");
    CdrWriter newer(CDR2_LE, true, true);
    std::size_t inner = newer.begin_dheader();
    newer.u32(1).u32(2).u32(333).end_dheader(inner);  // 333: a member this reader does not know
    newer.u32(4);
    const DecodedValue from_newer = decoded(newer.bytes(), "Outer");
    EXPECT_EQ(member(member(from_newer, "inner"), "b").unsigned_integer, 2u);
    EXPECT_EQ(member(from_newer, "after").unsigned_integer, 4u);

    CdrWriter older(CDR2_LE, true, true);
    inner = older.begin_dheader();
    older.u32(1).end_dheader(inner);
    older.u32(4);
    const DecodedValue from_older = decoded(older.bytes(), "Outer");
    EXPECT_EQ(member(from_older, "inner").fields.size(), 1u);
    EXPECT_EQ(member(from_older, "after").unsigned_integer, 4u);
}

TEST_F(CdrDecoderTest, TakesAnUnannotatedStructAsTheEncapsulationSays) {
    add_idl("struct Plain { uint32 a; };");
    CdrWriter delimited(D_CDR2_LE, true, true);
    const std::size_t header = delimited.begin_dheader();
    delimited.u32(5).end_dheader(header);
    EXPECT_EQ(member(decoded(delimited.bytes(), "Plain"), "a").unsigned_integer, 5u);

    CdrWriter plain(CDR2_LE, true, true);
    plain.u32(6);
    EXPECT_EQ(member(decoded(plain.bytes(), "Plain"), "a").unsigned_integer, 6u);
}

TEST_F(CdrDecoderTest, DecodesEnumsByNameArraysByDimensionTypedefsAndInheritedMembersFirst) {
    add_idl(R"(
        module m {
            const long N = 2;
            enum Color { RED, @value(5) GREEN, BLUE };
            typedef double Vec3[3];
            typedef sequence<Color, N + 1> Colors;
            struct Base { int8 id; };
            struct Derived : Base {
                Color color;
                Colors history;
                Vec3 position;
                int16 grid[N][3];
                char letter;
                boolean on;
                float ratio;
            };
        };)");
    CdrWriter payload(CDR_LE, true, false);
    payload.u8(0xff).u32(6).u32(2).u32(0).u32(9);
    payload.f64(1).f64(2).f64(3);
    for (std::uint16_t i = 0; i < 6; ++i)
        payload.u16(i);
    payload.u8('x').u8(1);
    const float ratio = 0.1f;
    std::uint32_t bits = 0;
    std::memcpy(&bits, &ratio, sizeof bits);
    payload.u32(bits);

    const DecodedValue sut = decoded(payload.bytes(), "m::Derived");
    ASSERT_GE(sut.fields.size(), 2u);
    EXPECT_EQ(sut.fields[0].first, "id");
    EXPECT_EQ(member(sut, "id").signed_integer, -1);
    EXPECT_EQ(member(sut, "color").text, "BLUE");
    EXPECT_EQ(member(sut, "color").signed_integer, 6);
    ASSERT_EQ(member(sut, "history").items.size(), 2u);
    EXPECT_EQ(member(sut, "history").items[0].text, "RED");
    EXPECT_EQ(member(sut, "history").items[1].text, "");  // 9: no such enumerator
    EXPECT_EQ(member(sut, "history").items[1].signed_integer, 9);
    EXPECT_EQ(member(sut, "position").items[2].real, 3.0);
    const DecodedValue& grid = member(sut, "grid");
    ASSERT_EQ(grid.items.size(), 2u);
    ASSERT_EQ(grid.items[1].items.size(), 3u);
    EXPECT_EQ(grid.items[1].items[2].signed_integer, 5);
    EXPECT_EQ(member(sut, "letter").text, "x");
    EXPECT_TRUE(member(sut, "on").boolean);
    EXPECT_TRUE(member(sut, "ratio").single_precision);
    EXPECT_EQ(member(sut, "ratio").real, static_cast<double>(0.1f));
}

TEST_F(CdrDecoderTest, EnforcesTheBoundsOfStringsAndSequences) {
    add_idl("struct Short { string<3> s; }; struct Few { sequence<octet, 2> b; };");
    CdrWriter long_string(CDR_LE, true, false);
    long_string.str("abcd");
    EXPECT_EQ(decode(long_string.bytes(), "Short").error, "s: a string of 4 characters, over its bound 3");
    CdrWriter many(CDR_LE, true, false);
    many.u32(3).u8(1).u8(2).u8(3);
    EXPECT_EQ(decode(many.bytes(), "Few").error, "b: a sequence of 3 elements, over its bound 2");
}

TEST_F(CdrDecoderTest, RefusesACountNoPayloadOfThisSizeCouldHoldWithoutAllocatingIt) {
    add_idl("struct Empty {}; struct Lots { sequence<Empty> nothing; }; struct Bytes { sequence<octet> b; };");
    CdrWriter payload(CDR_LE, true, false);
    payload.u32(0xffffffffu);
    const CdrDecodeResult empties = decode(payload.bytes(), "Lots");
    EXPECT_FALSE(empties.value.has_value());
    EXPECT_NE(empties.error.find("4294967295 elements"), std::string::npos) << empties.error;
    const CdrDecodeResult bytes = decode(payload.bytes(), "Bytes");
    EXPECT_FALSE(bytes.value.has_value());
}

TEST_F(CdrDecoderTest, SaysWhatItCannotDecodeInsteadOfGuessing) {
    add_idl(R"(
        @mutable struct Changing { long a; };
        struct Maybe { @optional long a; };
        struct Wide { wstring w; };
        union U switch (long) { case 1: long a; };
        struct WithUnion { U u; };)");
    CdrWriter payload(CDR_LE, true, false);
    payload.u32(1).u32(1);
    EXPECT_EQ(decode(payload.bytes(), "Changing").error, "cannot decode Changing: @mutable structs are not supported");
    EXPECT_EQ(decode(payload.bytes(), "Maybe").error, "a: cannot decode Maybe: @optional members are not supported");
    EXPECT_EQ(decode(payload.bytes(), "Wide").error, "w: cannot decode wstring (test.idl:4)");
    EXPECT_EQ(decode(payload.bytes(), "WithUnion").error, "u: cannot decode union U: not supported");
    EXPECT_EQ(decode(payload.bytes(), "no::Such").error, "no IDL for the type no::Such");

    CdrWriter parameter_list(0x0003, true, false);
    parameter_list.u32(1);
    EXPECT_EQ(decode(parameter_list.bytes(), "tgw::idl::KeyedReading").error,
              "encapsulation 0x0003 (parameter list, a @mutable type): cannot decode");
}

}  // namespace
}  // namespace tgw::test
