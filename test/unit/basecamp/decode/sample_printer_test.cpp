#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "GatewayStatus.h"
#include "KeyedReading.h"

#include "base/utc_text.hpp"
#include "basecamp/decode/sample_printer.hpp"
#include "basecamp/decode/value_json.hpp"
#include "basecamp/decode/value_text.hpp"
#include "test/unit/types/cdr_test_payloads.hpp"

namespace tgw::test {
namespace {

using basecamp::ReceivedSample;
using basecamp::SamplePrinter;
using eprosima::fastcdr::Cdr;
using types::DecodedValue;

constexpr std::int64_t STAMP_NS = 1'795'550'482'000'000'123;
const std::string INSTANCE = "00000007000000000000000000000000";

class SamplePrinterTest : public ::testing::Test {
  protected:
    void SetUp() override { types_.add_project_types(); }

    std::string print(const std::string& type, SamplePrinter::Format format, const ReceivedSample& sample) const {
        const SamplePrinter sut(types_, type, format);
        std::ostringstream out;
        sut.print(out, sample);
        return out.str();
    }

    static ReceivedSample reading_sample() {
        idl::KeyedReading reading;
        reading.sensor_id(7);
        reading.value(21.5);
        reading.label("north \"gate\"");
        ReceivedSample sample;
        sample.payload = fastcdr_payload(reading, Cdr::LITTLE_ENDIANNESS);
        sample.source = base::wall_from_ns(STAMP_NS);
        sample.instance = INSTANCE;
        return sample;
    }

    types::TypeLibrary types_;
};

TEST_F(SamplePrinterTest, PrintsASampleAsTextFieldByFieldAfterItsTimestampAndInstance) {
    EXPECT_EQ(print("tgw::idl::KeyedReading", SamplePrinter::Format::text, reading_sample()),
              "# source_timestamp: 2026-11-24T20:01:22.000000123Z\n"
              "# instance: 00000007000000000000000000000000\n"
              "sensor_id: 7\n"
              "value: 21.5\n"
              "label: \"north \\\"gate\\\"\"\n"
              "---\n");
}

TEST_F(SamplePrinterTest, PrintsOneJsonObjectALine) {
    EXPECT_EQ(print("tgw::idl::KeyedReading", SamplePrinter::Format::json, reading_sample()),
              "{\"source_timestamp_ns\":1795550482000000123,\"instance\":\"00000007000000000000000000000000\","
              "\"data\":{\"sensor_id\":7,\"value\":21.5,\"label\":\"north \\\"gate\\\"\"}}\n");
}

TEST_F(SamplePrinterTest, PrintsSizeAndHexWithTheReasonWhenTheTypeHasNoIdl) {
    ReceivedSample sample;
    sample.payload = {0x00, 0x01, 0x00, 0x00, 0x2a, 0x00, 0x00, 0x00};
    EXPECT_EQ(print("vendor::Opaque", SamplePrinter::Format::text, sample),
              "# cannot decode: no IDL for the type vendor::Opaque\n"
              "size_bytes: 8\n"
              "hex: 000100002a000000\n"
              "---\n");
    EXPECT_EQ(print("vendor::Opaque", SamplePrinter::Format::json, sample),
              "{\"size_bytes\":8,\"hex\":\"000100002a000000\",\"error\":\"no IDL for the type vendor::Opaque\"}\n");
}

TEST_F(SamplePrinterTest, PrintsATruncatedSampleAsSizeAndHex) {
    ReceivedSample sample = reading_sample();
    sample.payload.resize(sample.payload.size() - 3);
    const std::string sut = print("tgw::idl::KeyedReading", SamplePrinter::Format::text, sample);
    EXPECT_NE(sut.find("# cannot decode: label: needs"), std::string::npos) << sut;
    EXPECT_NE(sut.find("size_bytes: " + std::to_string(sample.payload.size()) + "\n"), std::string::npos) << sut;
}

TEST_F(SamplePrinterTest, IndentsNestedStructsAndListsOfStructsAsRos2TopicEchoDoes) {
    idl::GatewayStatus status;
    status.gateway_prefix({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
    status.sensor("fixed:20000");
    idl::TopicStatus topic;
    topic.name("telemetry/A");
    topic.ttl_ms(1000);
    status.topics({topic, topic});
    ReceivedSample sample;
    sample.payload = fastcdr_payload(status, Cdr::BIG_ENDIANNESS);
    const std::string sut = print("tgw::idl::GatewayStatus", SamplePrinter::Format::text, sample);
    EXPECT_EQ(sut.rfind("gateway_prefix: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]\nrobot_name: \"\"\nsent_ns: 0\n", 0),
              0u)
        << sut;
    EXPECT_NE(sut.find("\nsensor: \"fixed:20000\"\n"), std::string::npos) << sut;
    EXPECT_NE(sut.find("\ntopics:\n- name: \"telemetry/A\"\n  ttl_ms: 1000\n  queued_samples: 0\n"), std::string::npos)
        << sut;
    // The list of structs indented, and the members after it back at the top level.
    const std::string end =
        "  active_ms: 0\nuplink_topics: []\nuplink_charged: false\nuplink_wire_bytes: 0\nbackfill_rows: 0\n"
        "backfill_bytes: 0\nbackfill_oldest_ns: 0\nbackfill_sent: 0\nbackfill_acknowledged: 0\n---\n";
    EXPECT_EQ(sut.compare(sut.size() - end.size(), end.size(), end), 0) << sut;
}

TEST(ValueTextTest, CutsLongListsOfScalarsButJsonKeepsThemWhole) {
    types::DecodedValue list;
    list.kind = types::DecodedValue::Kind::list;
    for (int i = 0; i < 5; ++i) {
        types::DecodedValue item;
        item.kind = types::DecodedValue::Kind::unsigned_integer;
        item.unsigned_integer = static_cast<std::uint64_t>(i);
        list.items.push_back(item);
    }
    types::DecodedValue record;
    record.fields.emplace_back("data", list);
    std::ostringstream text;
    basecamp::write_text(text, record, 3);
    EXPECT_EQ(text.str(), "data: [0, 1, 2, '... 2 more']\n");
    std::ostringstream json;
    basecamp::write_json(json, record);
    EXPECT_EQ(json.str(), "{\"data\":[0,1,2,3,4]}");
}

TEST(ValueJsonTest, WritesRealsWithTheirShortestDigitsAndNanAndInfinityAsStrings) {
    const auto real = [](double value, bool single) {
        types::DecodedValue v;
        v.kind = types::DecodedValue::Kind::real;
        v.real = value;
        v.single_precision = single;
        return basecamp::json_scalar(v);
    };
    EXPECT_EQ(real(0.1, false), "0.1");
    EXPECT_EQ(real(static_cast<double>(0.1f), true), "0.1");
    EXPECT_EQ(real(21.0, false), "21.0");
    EXPECT_EQ(real(1e300, false), "1e+300");
    EXPECT_EQ(real(std::numeric_limits<double>::quiet_NaN(), false), "\"nan\"");
    EXPECT_EQ(real(-std::numeric_limits<double>::infinity(), false), "\"-inf\"");
}

TEST(ValueJsonTest, EscapesControlCharactersAndBytesThatAreNotUtf8) {
    EXPECT_EQ(basecamp::json_string("a\"b\\c\nd\x01"), "\"a\\\"b\\\\c\\nd\\u0001\"");
    EXPECT_EQ(basecamp::json_string("caf\xc3\xa9 \xe2\x82\xac"), "\"caf\xc3\xa9 \xe2\x82\xac\"");  // kept
    EXPECT_EQ(basecamp::json_string("\xff\xc3(\xed\xa0\x80"), "\"\\u00ff\\u00c3(\\u00ed\\u00a0\\u0080\"");
}

TEST(UtcTextTest, WritesIso8601WithNanoseconds) {
    EXPECT_EQ(base::utc_text(base::wall_from_ns(0)), "1970-01-01T00:00:00.000000000Z");
    EXPECT_EQ(base::utc_text(base::wall_from_ns(STAMP_NS)), "2026-11-24T20:01:22.000000123Z");
}

}  // namespace
}  // namespace tgw::test
