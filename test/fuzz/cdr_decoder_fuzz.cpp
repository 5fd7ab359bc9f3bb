// tm-basecamp echo decodes payloads off the network: any bytes, as any known type, give a value or an error,
// never a read out of bounds; a value prints as text and JSON, and bytes after it change nothing.
// Input: one byte choosing the type (of the project's and a few XCDR2 ones), then the payload.
#include <algorithm>
#include <sstream>

#include "GatewayStatus.h"
#include "KeyedReading.h"
#include "PaperWorkload.h"
#include "RosString.h"

#include "basecamp/decode/sample_printer.hpp"
#include "basecamp/decode/value_json.hpp"
#include "test/fuzz/fuzz_target.hpp"
#include "test/unit/types/cdr_test_payloads.hpp"
#include "types/cdr_decoder.hpp"

namespace tgw::fuzz {

namespace {

// Types for the XCDR2 paths the project's own types do not take: DHEADERs, enums, arrays, inheritance.
constexpr const char* XCDR2_IDL = R"(
module fz {
    enum Mode { IDLE, RUN, @value(7) STOP };
    @appendable struct Item { string name; sequence<int16, 8> values; };
    @final struct Base { uint8 flag; };
    @appendable struct Frame : Base {
        uint64 stamp;
        Mode mode;
        sequence<Item> items;
        double grid[2][2];
        string<16> label;
        char c;
        boolean on;
        float ratio;
    };
};
)";

const types::TypeLibrary& library() {
    static const types::TypeLibrary types = [] {
        types::TypeLibrary t;
        t.add_project_types();
        std::istringstream in(XCDR2_IDL);
        t.add_idl(in, "fuzz.idl");
        t.check_references();
        return t;
    }();
    return types;
}

const std::vector<std::string>& type_names() {
    static const std::vector<std::string> names = library().struct_names();
    return names;
}

std::string input_for(const std::string& type, const std::vector<std::uint8_t>& payload) {
    const auto& names = type_names();
    const auto index = std::find(names.begin(), names.end(), type) - names.begin();
    return std::string(1, static_cast<char>(index)) + std::string(payload.begin(), payload.end());
}

/// fz::Frame in XCDR2 little endian (D_CDR2_LE), laid out by hand; its one Item is of an older version, without
/// `values`.
std::vector<std::uint8_t> xcdr2_frame() {
    return {0x00, 0x09, 0x00, 0x00,                          // D_CDR2_LE
            0x50, 0x00, 0x00, 0x00,                          // DHEADER: 80 bytes
            0x01, 0x00, 0x00, 0x00,                          // flag (Base), padding
            0x05, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // stamp, aligned to 4
            0x07, 0x00, 0x00, 0x00,                          // mode STOP
            0x0e, 0x00, 0x00, 0x00,                          // items' DHEADER: 14 bytes
            0x01, 0x00, 0x00, 0x00,                          // 1 item
            0x06, 0x00, 0x00, 0x00,                          // the item's DHEADER: 6 bytes
            0x02, 0x00, 0x00, 0x00, 'a',  0x00, 0x00, 0x00,  // name "a", padding
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xf0, 0x3f,  // grid 1.0
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x40,  // 2.0
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08, 0x40,  // 3.0
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x10, 0x40,  // 4.0
            0x02, 0x00, 0x00, 0x00, 'b',  0x00, 'x',  0x01,  // label "b", c, on
            0x00, 0x00, 0x80, 0x3f};                         // ratio 1.0f
}

}  // namespace

std::vector<std::string> seeds() {
    using eprosima::fastcdr::Cdr;
    using test::fastcdr_payload;
    idl::GatewayStatus status;
    status.sensor("qdisc:veth0");
    status.gateway_prefix({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
    idl::TopicStatus topic;
    topic.name("telemetry/A");
    topic.ttl_ms(1000);
    status.topics({topic, topic});
    idl::KeyedReading reading;
    reading.sensor_id(7);
    reading.label("north");
    idl::PaperMessage paper;
    paper.data(std::vector<std::uint8_t>(41, 0x5a));
    std_msgs::msg::dds_::String_ chatter;
    chatter.data("Hello World: 1");
    return {
        input_for("tgw::idl::GatewayStatus", fastcdr_payload(status, Cdr::LITTLE_ENDIANNESS)),
        input_for("tgw::idl::GatewayStatus", fastcdr_payload(status, Cdr::BIG_ENDIANNESS)),
        input_for("tgw::idl::KeyedReading", fastcdr_payload(reading, Cdr::BIG_ENDIANNESS)),
        input_for("tgw::idl::PaperMessage", fastcdr_payload(paper, Cdr::LITTLE_ENDIANNESS)),
        input_for("std_msgs::msg::dds_::String_", fastcdr_payload(chatter, Cdr::LITTLE_ENDIANNESS)),
        input_for("fz::Frame", xcdr2_frame()),
    };
}

}  // namespace tgw::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace tgw;
    if (size == 0)
        return 0;
    const std::string& type = fuzz::type_names()[data[0] % fuzz::type_names().size()];
    // A buffer of exactly the payload's size, so that AddressSanitizer sees any read past it.
    const std::vector<std::uint8_t> payload(data + 1, data + size);
    const types::CdrDecodeResult result = types::decode_cdr(payload.data(), payload.size(), type, fuzz::library());
    TGW_FUZZ_CHECK(result.value.has_value() == result.error.empty());
    if (!result.value)
        return 0;

    std::ostringstream json;
    basecamp::write_json(json, *result.value);
    TGW_FUZZ_CHECK(json.str().front() == '{' && json.str().back() == '}');
    basecamp::ReceivedSample sample;
    sample.payload = payload;
    std::ostringstream text;
    basecamp::SamplePrinter(fuzz::library(), type, basecamp::SamplePrinter::Format::text).print(text, sample);
    TGW_FUZZ_CHECK(text.str().size() >= 4 && text.str().compare(text.str().size() - 4, 4, "---\n") == 0);

    std::vector<std::uint8_t> longer = payload;
    longer.insert(longer.end(), {0xde, 0xad, 0xbe});
    const types::CdrDecodeResult again = types::decode_cdr(longer.data(), longer.size(), type, fuzz::library());
    TGW_FUZZ_CHECK(again.value.has_value());
    std::ostringstream json_again;
    basecamp::write_json(json_again, *again.value);
    TGW_FUZZ_CHECK(json_again.str() == json.str());
    return 0;
}
