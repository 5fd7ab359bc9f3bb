#include "types/cdr_decoder.hpp"

#include <algorithm>
#include <cstring>
#include <limits>

#include "base/byte_order.hpp"

namespace tgw::types {

namespace {

using Kind = IdlType::Kind;

constexpr std::size_t ENCAPSULATION_BYTES = 4;
// Deeper nesting than any real type has: a typedef loop or a recursive type on a crafted payload ends here
// instead of on the stack's end.
constexpr int MAX_DEPTH = 100;

// RTPS encapsulation identifiers (XTypes 1.3, 7.6.3.1.2); the low bit is the byte order (1: little endian).
constexpr std::uint16_t CDR_LE = 0x0001;
constexpr std::uint16_t CDR2_BE = 0x0006;
constexpr std::uint16_t D_CDR2_LE = 0x0009;

class Decoder {
  public:
    Decoder(const std::uint8_t* data, std::size_t size, const TypeLibrary& types, bool little_endian, bool xcdr2,
            IdlExtensibility unannotated)
        : data_(data),
          limit_(size),
          types_(types),
          little_endian_(little_endian),
          xcdr2_(xcdr2),
          unannotated_(unannotated),
          // Every value but an empty struct takes at least a byte, and every struct or list holds a value or is
          // empty: more values than this means a crafted count of empty structs.
          max_values_(2 * size + 4096) {}

    /// Decodes the struct's first `member_limit` members (its base's counted first), the rest left unread.
    bool run(const IdlStruct& type, DecodedValue& out, std::size_t member_limit) {
        top_record_ = &out;
        member_limit_ = member_limit;
        return structure(type, out);
    }

    /// The error and where it happened, once run() returned false.
    std::string error() const {
        std::string path;
        for (auto it = path_.rbegin(); it != path_.rend(); ++it) {
            if (!path.empty() && (*it)[0] != '[')
                path += '.';
            path += *it;
        }
        return path.empty() ? error_ : path + ": " + error_;
    }

  private:
    bool fail(std::string what) {
        error_ = std::move(what);
        return false;
    }

    /// Unwinding a failure: records the member or index it happened in.
    bool failed_in(std::string where) {
        path_.push_back(std::move(where));
        return false;
    }

    std::size_t left() const { return limit_ - pos_; }

    bool need(std::size_t bytes) {
        if (bytes <= left())
            return true;
        return fail("needs " + std::to_string(bytes) + " bytes at offset " + std::to_string(pos_) + ", " +
                    std::to_string(left()) + " are left");
    }

    /// Alignment is relative to the first byte after the encapsulation header; XCDR2 aligns to 4 at most.
    bool align(std::size_t size) {
        if (xcdr2_)
            size = std::min<std::size_t>(size, 4);
        const std::size_t offset = pos_ - ENCAPSULATION_BYTES;
        const std::size_t padding = (size - offset % size) % size;
        if (!need(padding))
            return false;
        pos_ += padding;
        return true;
    }

    template <typename U>
    bool read(U& value) {
        if (!align(sizeof(U)) || !need(sizeof(U)))
            return false;
        value = base::load_unsigned<U>(data_ + pos_, little_endian_);
        pos_ += sizeof(U);
        return true;
    }

    bool count_value() {
        if (++values_ <= max_values_)
            return true;
        return fail("more than " + std::to_string(max_values_) + " values in a payload of " + std::to_string(limit_) +
                    " bytes");
    }

    /// Decodes with `decode` what follows, after XCDR2's delimiter when `delimited`: the byte size of what follows,
    /// which then bounds it. What is left inside it afterwards (members a newer version of the type appended) is
    /// skipped.
    template <typename Decode>
    bool within(bool delimited, Decode decode) {
        if (!delimited)
            return decode();
        std::uint32_t size = 0;
        if (!read(size))
            return false;
        if (size > left())
            return fail("a DHEADER of " + std::to_string(size) + " bytes at offset " + std::to_string(pos_ - 4) + ", " +
                        std::to_string(left()) + " are left");
        const std::size_t saved_limit = limit_;
        limit_ = pos_ + size;
        if (!decode())
            return false;
        pos_ = limit_;
        limit_ = saved_limit;
        return true;
    }

    IdlExtensibility extensibility(const IdlStruct& type) const {
        return type.extensibility == IdlExtensibility::unspecified ? unannotated_ : type.extensibility;
    }

    bool structure(const IdlStruct& type, DecodedValue& out) {
        if (extensibility(type) == IdlExtensibility::mutable_)
            return fail("cannot decode " + type.name + ": @mutable structs are not supported");
        out.kind = DecodedValue::Kind::record;
        return within(xcdr2_ && extensibility(type) == IdlExtensibility::appendable,
                      [&] { return members(type, out, 0); });
    }

    /// The base's members first, then the struct's own, all under the struct's one DHEADER.
    bool members(const IdlStruct& type, DecodedValue& out, int depth) {
        if (depth > MAX_DEPTH)
            return fail("inheritance deeper than " + std::to_string(MAX_DEPTH));
        if (type.base) {
            const IdlDeclaration* base = types_.resolve(type.base->name, type.base->scope);
            const auto* base_struct = base ? std::get_if<IdlStruct>(base) : nullptr;
            if (base_struct == nullptr)
                return fail(type.name + ": its base '" + type.base->name + "' is not a known struct");
            if (!members(*base_struct, out, depth + 1))
                return false;
        }
        for (const IdlMember& member : type.members) {
            if (&out == top_record_ && out.fields.size() >= member_limit_)
                break;
            if (member.optional) {
                fail("cannot decode " + type.name + ": @optional members are not supported");
                return failed_in(member.name);
            }
            // An appendable struct of an older version of the type ends early: the rest is absent.
            if (xcdr2_ && extensibility(type) == IdlExtensibility::appendable && left() == 0)
                break;
            out.fields.emplace_back(member.name, DecodedValue{});
            if (!value(member.type, out.fields.back().second))
                return failed_in(member.name);
        }
        return true;
    }

    bool value(const IdlType& type, DecodedValue& out) {
        if (++depth_ > MAX_DEPTH)
            return fail("nesting deeper than " + std::to_string(MAX_DEPTH));
        const bool ok = count_value() && dispatch(type, out);
        --depth_;
        return ok;
    }

    bool dispatch(const IdlType& type, DecodedValue& out) {
        switch (type.kind) {
            case Kind::string:
                return string(type, out);
            case Kind::sequence:
                return sequence(type, out);
            case Kind::array:
                return array(type, out);
            case Kind::named:
                return named(type, out);
            case Kind::unsupported:
                return fail("cannot decode " + type.name + " (" + type.where.text() + ")");
            default:
                return primitive(type.kind, out);
        }
    }

    bool primitive(Kind kind, DecodedValue& out) {
        switch (kind) {
            case Kind::boolean:
                return scalar<std::uint8_t>(out, [](DecodedValue& v, std::uint8_t x) {
                    v.kind = DecodedValue::Kind::boolean;
                    v.boolean = x != 0;
                });
            case Kind::char8:
                return scalar<std::uint8_t>(out, [](DecodedValue& v, std::uint8_t x) {
                    v.kind = DecodedValue::Kind::character;
                    v.text.assign(1, static_cast<char>(x));
                });
            case Kind::octet:
            case Kind::uint8:
                return unsigned_integer<std::uint8_t>(out);
            case Kind::uint16:
                return unsigned_integer<std::uint16_t>(out);
            case Kind::uint32:
                return unsigned_integer<std::uint32_t>(out);
            case Kind::uint64:
                return unsigned_integer<std::uint64_t>(out);
            case Kind::int8:
                return signed_integer<std::uint8_t, std::int8_t>(out);
            case Kind::int16:
                return signed_integer<std::uint16_t, std::int16_t>(out);
            case Kind::int32:
                return signed_integer<std::uint32_t, std::int32_t>(out);
            case Kind::int64:
                return signed_integer<std::uint64_t, std::int64_t>(out);
            case Kind::float32:
                return real<std::uint32_t, float>(out);
            case Kind::float64:
                return real<std::uint64_t, double>(out);
            default:
                return fail("not a primitive type");
        }
    }

    template <typename U, typename Set>
    bool scalar(DecodedValue& out, Set set) {
        U raw = 0;
        if (!read(raw))
            return false;
        set(out, raw);
        return true;
    }

    template <typename U>
    bool unsigned_integer(DecodedValue& out) {
        return scalar<U>(out, [](DecodedValue& v, U x) {
            v.kind = DecodedValue::Kind::unsigned_integer;
            v.unsigned_integer = x;
        });
    }

    template <typename U, typename S>
    bool signed_integer(DecodedValue& out) {
        return scalar<U>(out, [](DecodedValue& v, U x) {
            v.kind = DecodedValue::Kind::signed_integer;
            v.signed_integer = static_cast<S>(x);
        });
    }

    template <typename U, typename F>
    bool real(DecodedValue& out) {
        return scalar<U>(out, [](DecodedValue& v, U bits) {
            F x = 0;
            std::memcpy(&x, &bits, sizeof x);
            v.kind = DecodedValue::Kind::real;
            v.real = x;
            v.single_precision = sizeof(F) == sizeof(float);
        });
    }

    bool string(const IdlType& type, DecodedValue& out) {
        std::uint32_t length = 0;
        if (!read(length) || !need(length))
            return false;
        // The length counts the terminating NUL; some writers send 0 for an empty string.
        std::size_t chars = length;
        if (chars > 0 && data_[pos_ + chars - 1] == '\0')
            --chars;
        if (type.bound != 0 && chars > type.bound)
            return fail("a string of " + std::to_string(chars) + " characters, over its bound " +
                        std::to_string(type.bound));
        out.kind = DecodedValue::Kind::string;
        out.text.assign(reinterpret_cast<const char*>(data_ + pos_), chars);
        pos_ += length;
        return true;
    }

    /// Primitives and enums: XCDR2 puts no DHEADER before a sequence or array of them.
    bool primitive_element(const IdlType& type) const {
        const IdlType* current = &type;
        for (int hops = 0; hops < MAX_DEPTH; ++hops) {
            if (current->primitive_size() > 0)
                return true;
            if (current->kind != Kind::named)
                return false;
            const IdlDeclaration* declared = types_.resolve(current->name, current->scope);
            if (declared == nullptr)
                return false;
            if (std::holds_alternative<IdlEnum>(*declared))
                return true;
            const auto* alias = std::get_if<IdlTypedef>(declared);
            if (alias == nullptr)
                return false;
            current = &alias->type;
        }
        return false;
    }

    bool sequence(const IdlType& type, DecodedValue& out) {
        return within(xcdr2_ && !primitive_element(*type.element), [&] {
            std::uint32_t count = 0;
            if (!read(count))
                return false;
            if (type.bound != 0 && count > type.bound)
                return fail("a sequence of " + std::to_string(count) + " elements, over its bound " +
                            std::to_string(type.bound));
            return elements(*type.element, count, out);
        });
    }

    bool array(const IdlType& type, DecodedValue& out) {
        return within(xcdr2_ && !primitive_element(*type.element), [&] { return dimension(type, 0, out); });
    }

    /// x[2][3]: a list of 2 lists of 3, serialized as 6 elements in a row.
    bool dimension(const IdlType& type, std::size_t index, DecodedValue& out) {
        if (index + 1 == type.dimensions.size())
            return elements(*type.element, type.dimensions[index], out);
        out.kind = DecodedValue::Kind::list;
        const std::uint32_t count = type.dimensions[index];
        if (count > max_values_ - values_)
            return fail("an array of " + std::to_string(count) + " elements, more than a payload this size holds");
        out.items.resize(count);
        for (std::uint32_t i = 0; i < count; ++i) {
            if (!count_value() || !dimension(type, index + 1, out.items[i]))
                return failed_in("[" + std::to_string(i) + "]");
        }
        return true;
    }

    bool elements(const IdlType& element, std::uint32_t count, DecodedValue& out) {
        out.kind = DecodedValue::Kind::list;
        if (count > max_values_ - values_)
            return fail(std::to_string(count) + " elements, more than a payload of " + std::to_string(limit_) +
                        " bytes holds");
        out.items.reserve(std::min<std::size_t>(count, left()));
        for (std::uint32_t i = 0; i < count; ++i) {
            out.items.emplace_back();
            if (!value(element, out.items.back()))
                return failed_in("[" + std::to_string(i) + "]");
        }
        return true;
    }

    bool named(const IdlType& type, DecodedValue& out) {
        const IdlDeclaration* declared = types_.resolve(type.name, type.scope);
        if (declared == nullptr)
            return fail("unknown type '" + type.name + "' (" + type.where.text() + ")");
        if (const auto* nested = std::get_if<IdlStruct>(declared))
            return structure(*nested, out);
        if (const auto* enumeration = std::get_if<IdlEnum>(declared))
            return enumerator(*enumeration, out);
        if (const auto* alias = std::get_if<IdlTypedef>(declared))
            return value(alias->type, out);
        const auto& skipped = std::get<IdlUnsupported>(*declared);
        return fail("cannot decode " + skipped.what + " " + skipped.name + ": not supported");
    }

    bool enumerator(const IdlEnum& type, DecodedValue& out) {
        std::int64_t number = 0;
        bool ok = false;
        if (type.bit_bound <= 8) {
            std::uint8_t raw = 0;
            ok = read(raw);
            number = static_cast<std::int8_t>(raw);
        } else if (type.bit_bound <= 16) {
            std::uint16_t raw = 0;
            ok = read(raw);
            number = static_cast<std::int16_t>(raw);
        } else {
            std::uint32_t raw = 0;
            ok = read(raw);
            number = static_cast<std::int32_t>(raw);
        }
        if (!ok)
            return false;
        out.kind = DecodedValue::Kind::enumerator;
        out.signed_integer = number;
        for (const IdlEnumerator& candidate : type.enumerators) {
            if (candidate.value == number)
                out.text = candidate.name;
        }
        return true;
    }

    const std::uint8_t* data_;
    std::size_t pos_ = ENCAPSULATION_BYTES;
    std::size_t limit_;
    const TypeLibrary& types_;
    const bool little_endian_;
    const bool xcdr2_;
    const IdlExtensibility unannotated_;
    const std::size_t max_values_;
    std::size_t values_ = 0;
    int depth_ = 0;
    const DecodedValue* top_record_ = nullptr;
    std::size_t member_limit_ = 0;
    std::string error_;
    std::vector<std::string> path_;
};

std::string hex16(std::uint16_t value) {
    static const char DIGITS[] = "0123456789abcdef";
    std::string text = "0x";
    for (int shift = 12; shift >= 0; shift -= 4)
        text += DIGITS[(value >> shift) & 0xf];
    return text;
}

}  // namespace

CdrDecodeResult decode_cdr(const std::uint8_t* data, std::size_t size, const std::string& type_name,
                           const TypeLibrary& types, std::size_t member_limit) {
    CdrDecodeResult result;
    const IdlDeclaration* declared = types.find(type_name);
    const IdlStruct* type = declared ? std::get_if<IdlStruct>(declared) : nullptr;
    if (type == nullptr) {
        result.error = declared ? type_name + " is not a struct" : "no IDL for the type " + type_name;
        return result;
    }
    if (size < ENCAPSULATION_BYTES) {
        result.error = std::to_string(size) + " bytes: shorter than the encapsulation header";
        return result;
    }
    const std::uint16_t encapsulation = static_cast<std::uint16_t>(data[0] << 8 | data[1]);
    const bool little_endian = (encapsulation & 1) != 0;
    if (encapsulation > D_CDR2_LE || (encapsulation > CDR_LE && encapsulation < CDR2_BE)) {
        result.error = "encapsulation " + hex16(encapsulation) +
                       ((encapsulation & ~1) == 0x0002 || (encapsulation & ~1) == 0x000a
                            ? " (parameter list, a @mutable type): cannot decode"
                            : ": not a CDR encoding this decoder knows");
        return result;
    }
    const bool xcdr2 = encapsulation >= CDR2_BE;
    const IdlExtensibility unannotated =
        (encapsulation & ~1) == 0x0008 ? IdlExtensibility::appendable : IdlExtensibility::final;
    Decoder decoder(data, size, types, little_endian, xcdr2, unannotated);
    DecodedValue value;
    if (decoder.run(*type, value, member_limit))
        result.value = std::move(value);
    else
        result.error = decoder.error();
    return result;
}

}  // namespace tgw::types
