#pragma once

// A strict JSON reader for checking what programs print (tm-basecamp echo --json), member by member. Numbers keep
// their text, so 64-bit integers compare exactly.
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace tgw::test {

struct Json {
    enum class Kind { null, boolean, number, string, array, object };

    Kind kind = Kind::null;
    bool boolean = false;
    std::string text;  ///< a string's value, or a number as written
    std::vector<Json> items;
    std::vector<std::pair<std::string, Json>> members;

    /// The member `name`, or a null value when there is none.
    const Json& operator[](const std::string& name) const {
        for (const auto& [key, value] : members) {
            if (key == name)
                return value;
        }
        static const Json none;
        return none;
    }
    bool has(const std::string& name) const {
        for (const auto& member : members) {
            if (member.first == name)
                return true;
        }
        return false;
    }
    std::uint64_t as_uint() const { return std::strtoull(text.c_str(), nullptr, 10); }
    std::int64_t as_int() const { return std::strtoll(text.c_str(), nullptr, 10); }
    double as_double() const { return std::strtod(text.c_str(), nullptr); }
};

/// `text` as one JSON value with nothing after it; nullopt when it is not exactly that.
inline std::optional<Json> parse_json(const std::string& text) {
    struct Reader {
        const std::string& s;
        std::size_t i = 0;

        void space() {
            while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\n' || s[i] == '\r'))
                ++i;
        }
        bool literal(const char* word) {
            const std::string w(word);
            if (s.compare(i, w.size(), w) != 0)
                return false;
            i += w.size();
            return true;
        }
        bool string(std::string& out) {
            if (i >= s.size() || s[i] != '"')
                return false;
            for (++i; i < s.size() && s[i] != '"'; ++i) {
                if (static_cast<unsigned char>(s[i]) < 0x20)
                    return false;
                if (s[i] != '\\') {
                    out += s[i];
                    continue;
                }
                if (++i >= s.size())
                    return false;
                const char e = s[i];
                if (e == 'u') {
                    if (i + 4 >= s.size())
                        return false;
                    const long code = std::strtol(s.substr(i + 1, 4).c_str(), nullptr, 16);
                    i += 4;
                    if (code < 0x80) {
                        out += static_cast<char>(code);
                    } else {  // enough for the tests: \u00XX and the BMP
                        if (code < 0x800) {
                            out += static_cast<char>(0xc0 | (code >> 6));
                        } else {
                            out += static_cast<char>(0xe0 | (code >> 12));
                            out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
                        }
                        out += static_cast<char>(0x80 | (code & 0x3f));
                    }
                    continue;
                }
                const std::string from = "\"\\/bfnrt";
                const std::string to = "\"\\/\b\f\n\r\t";
                const auto at = from.find(e);
                if (at == std::string::npos)
                    return false;
                out += to[at];
            }
            if (i >= s.size())
                return false;
            ++i;
            return true;
        }
        bool number(std::string& out) {
            const std::size_t start = i;
            if (i < s.size() && s[i] == '-')
                ++i;
            while (i < s.size() && std::string("0123456789.eE+-").find(s[i]) != std::string::npos)
                ++i;
            out = s.substr(start, i - start);
            char* end = nullptr;
            std::strtod(out.c_str(), &end);
            return !out.empty() && *end == '\0';
        }
        bool value(Json& out, int depth) {
            if (depth > 64)
                return false;
            space();
            if (i >= s.size())
                return false;
            const char c = s[i];
            if (c == '{') {
                out.kind = Json::Kind::object;
                ++i;
                space();
                if (i < s.size() && s[i] == '}')
                    return ++i, true;
                while (true) {
                    space();
                    std::pair<std::string, Json> member;
                    if (!string(member.first))
                        return false;
                    space();
                    if (i >= s.size() || s[i++] != ':' || !value(member.second, depth + 1))
                        return false;
                    out.members.push_back(std::move(member));
                    space();
                    if (i < s.size() && s[i] == ',') {
                        ++i;
                        continue;
                    }
                    return i < s.size() && s[i++] == '}';
                }
            }
            if (c == '[') {
                out.kind = Json::Kind::array;
                ++i;
                space();
                if (i < s.size() && s[i] == ']')
                    return ++i, true;
                while (true) {
                    out.items.emplace_back();
                    if (!value(out.items.back(), depth + 1))
                        return false;
                    space();
                    if (i < s.size() && s[i] == ',') {
                        ++i;
                        continue;
                    }
                    return i < s.size() && s[i++] == ']';
                }
            }
            if (c == '"') {
                out.kind = Json::Kind::string;
                return string(out.text);
            }
            if (literal("true") || literal("false")) {
                out.kind = Json::Kind::boolean;
                out.boolean = s[i - 1] == 'e' && s[i - 2] == 'u';
                return true;
            }
            if (literal("null"))
                return true;
            out.kind = Json::Kind::number;
            return number(out.text);
        }
    };
    Reader reader{text};
    Json out;
    if (!reader.value(out, 0))
        return std::nullopt;
    reader.space();
    if (reader.i != text.size())
        return std::nullopt;
    return out;
}

}  // namespace tgw::test
