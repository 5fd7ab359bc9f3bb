#include "basecamp/decode/sample_printer.hpp"

#include <algorithm>
#include <cstdio>
#include <ctime>

#include "base/utc_text.hpp"
#include "basecamp/decode/value_json.hpp"
#include "basecamp/decode/value_text.hpp"
#include "types/cdr_decoder.hpp"

namespace tgw::basecamp {

namespace {

// A 60 kB camera frame in hex is no text to read: the text format shows its start, JSON all of it.
constexpr std::size_t TEXT_HEX_BYTES = 256;

}  // namespace

std::string hex_text(const std::uint8_t* bytes, std::size_t size) {
    static const char DIGITS[] = "0123456789abcdef";
    std::string text;
    text.reserve(2 * size);
    for (std::size_t i = 0; i < size; ++i) {
        text += DIGITS[bytes[i] >> 4];
        text += DIGITS[bytes[i] & 0xf];
    }
    return text;
}

SamplePrinter::SamplePrinter(const types::TypeLibrary& types, std::string type_name, Format format)
    : types_(types), type_name_(std::move(type_name)), format_(format) {}

void SamplePrinter::print(std::ostream& out, const ReceivedSample& sample) const {
    const types::CdrDecodeResult decoded =
        types::decode_cdr(sample.payload.data(), sample.payload.size(), type_name_, types_);
    const std::size_t size = sample.payload.size();
    if (format_ == Format::json) {
        out << '{';
        const char* separator = "";
        if (sample.source) {
            out << "\"source_timestamp_ns\":" << base::to_ns(*sample.source);
            separator = ",";
        }
        if (!sample.instance.empty()) {
            out << separator << "\"instance\":" << json_string(sample.instance);
            separator = ",";
        }
        if (decoded.value) {
            out << separator << "\"data\":";
            write_json(out, *decoded.value);
        } else {
            out << separator << "\"size_bytes\":" << size << ",\"hex\":\"" << hex_text(sample.payload.data(), size)
                << "\",\"error\":" << json_string(decoded.error);
        }
        out << "}\n";
        return;
    }
    if (sample.source)
        out << "# source_timestamp: " << base::utc_text(*sample.source) << '\n';
    if (!sample.instance.empty())
        out << "# instance: " << sample.instance << '\n';
    if (decoded.value) {
        write_text(out, *decoded.value);
    } else {
        const std::size_t shown = std::min(size, TEXT_HEX_BYTES);
        out << "# cannot decode: " << decoded.error << '\n'
            << "size_bytes: " << size << '\n'
            << "hex: " << hex_text(sample.payload.data(), shown);
        if (shown < size)
            out << "  # the first " << shown << " bytes";
        out << '\n';
    }
    out << "---\n";
}

}  // namespace tgw::basecamp
