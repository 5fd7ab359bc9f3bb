#include "basecamp/decode/value_json.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace tgw::basecamp {

namespace {

/// The length of the well-formed UTF-8 sequence at `s` (RFC 3629: no overlong forms, no surrogates), or 0.
std::size_t utf8_length(const unsigned char* s, std::size_t n) {
    const unsigned char c = s[0];
    if (c < 0x80)
        return 1;
    std::size_t length = 0;
    unsigned char low = 0x80;
    unsigned char high = 0xbf;
    if (c >= 0xc2 && c <= 0xdf) {
        length = 2;
    } else if (c >= 0xe0 && c <= 0xef) {
        length = 3;
        low = c == 0xe0 ? 0xa0 : 0x80;
        high = c == 0xed ? 0x9f : 0xbf;
    } else if (c >= 0xf0 && c <= 0xf4) {
        length = 4;
        low = c == 0xf0 ? 0x90 : 0x80;
        high = c == 0xf4 ? 0x8f : 0xbf;
    } else {
        return 0;
    }
    if (n < length || s[1] < low || s[1] > high)
        return 0;
    for (std::size_t i = 2; i < length; ++i) {
        if (s[i] < 0x80 || s[i] > 0xbf)
            return 0;
    }
    return length;
}

std::string real_text(const types::DecodedValue& value) {
    if (std::isnan(value.real))
        return "\"nan\"";
    if (std::isinf(value.real))
        return value.real > 0 ? "\"inf\"" : "\"-inf\"";
    char buffer[64];
    const auto result = value.single_precision
                            ? std::to_chars(buffer, buffer + sizeof buffer, static_cast<float>(value.real))
                            : std::to_chars(buffer, buffer + sizeof buffer, value.real);
    std::string text(buffer, result.ptr);
    // "21" is an integer to a reader; a real stays a real.
    if (text.find_first_of(".e") == std::string::npos)
        text += ".0";
    return text;
}

}  // namespace

std::string json_string(const std::string& text) {
    std::string out = "\"";
    const auto* bytes = reinterpret_cast<const unsigned char*>(text.data());
    for (std::size_t i = 0; i < text.size();) {
        const unsigned char c = bytes[i];
        char escaped[8];
        if (c == '"' || c == '\\') {
            out += '\\';
            out += static_cast<char>(c);
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\t') {
            out += "\\t";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c < 0x20 || c == 0x7f) {
            std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
            out += escaped;
        } else if (const std::size_t length = utf8_length(bytes + i, text.size() - i); length > 0) {
            out.append(text, i, length);
            i += length;
            continue;
        } else {
            std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
            out += escaped;
        }
        ++i;
    }
    out += '"';
    return out;
}

std::string json_scalar(const types::DecodedValue& value) {
    switch (value.kind) {
        case types::DecodedValue::Kind::boolean:
            return value.boolean ? "true" : "false";
        case types::DecodedValue::Kind::signed_integer:
            return std::to_string(value.signed_integer);
        case types::DecodedValue::Kind::unsigned_integer:
            return std::to_string(value.unsigned_integer);
        case types::DecodedValue::Kind::real:
            return real_text(value);
        case types::DecodedValue::Kind::character:
        case types::DecodedValue::Kind::string:
            return json_string(value.text);
        case types::DecodedValue::Kind::enumerator:
            return value.text.empty() ? std::to_string(value.signed_integer) : json_string(value.text);
        case types::DecodedValue::Kind::list:
        case types::DecodedValue::Kind::record:
            break;
    }
    return "null";
}

void write_json(std::ostream& out, const types::DecodedValue& value) {
    if (value.kind == types::DecodedValue::Kind::list) {
        out << '[';
        for (std::size_t i = 0; i < value.items.size(); ++i) {
            if (i > 0)
                out << ',';
            write_json(out, value.items[i]);
        }
        out << ']';
    } else if (value.kind == types::DecodedValue::Kind::record) {
        out << '{';
        for (std::size_t i = 0; i < value.fields.size(); ++i) {
            if (i > 0)
                out << ',';
            out << json_string(value.fields[i].first) << ':';
            write_json(out, value.fields[i].second);
        }
        out << '}';
    } else {
        out << json_scalar(value);
    }
}

}  // namespace tgw::basecamp
