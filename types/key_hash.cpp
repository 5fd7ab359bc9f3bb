#include "types/key_hash.hpp"

#include <algorithm>
#include <cstring>
#include <vector>

#include <openssl/evp.h>

#include "types/cdr_decoder.hpp"

namespace tgw::types {

namespace {

using Kind = IdlType::Kind;

constexpr std::uint16_t CDR2_BE = 0x0006;
// Deeper than any real type: a typedef loop ends here.
constexpr int MAX_DEPTH = 100;

/// A struct's members in the order of its decoded record's fields: the base's first.
void members_of(const TypeLibrary& types, const IdlStruct& type, std::vector<const IdlMember*>& out, int depth = 0) {
    if (depth > MAX_DEPTH)
        return;
    if (type.base) {
        const IdlDeclaration* base = types.resolve(type.base->name, type.base->scope);
        if (const auto* base_struct = base ? std::get_if<IdlStruct>(base) : nullptr)
            members_of(types, *base_struct, out, depth + 1);
    }
    for (const IdlMember& member : type.members)
        out.push_back(&member);
}

/// The positions, among members_of(), of the members that make the key: the @key ones, or every one when none is.
std::vector<std::size_t> key_positions(const std::vector<const IdlMember*>& members) {
    std::vector<std::size_t> keys;
    for (std::size_t i = 0; i < members.size(); ++i) {
        if (members[i]->key)
            keys.push_back(i);
    }
    if (keys.empty()) {
        for (std::size_t i = 0; i < members.size(); ++i)
            keys.push_back(i);
    }
    return keys;
}

std::size_t alignment(std::size_t size, bool xcdr2) {
    return xcdr2 ? std::min<std::size_t>(size, 4) : size;
}

std::size_t aligned(std::size_t offset, std::size_t size, bool xcdr2) {
    const std::size_t a = alignment(size, xcdr2);
    return (offset + a - 1) / a * a;
}

/// What a type is once its typedefs are followed: a type expression (primitive, string, sequence, array) or a
/// struct or enum declaration. Both null: unknown or unsupported.
struct Resolved {
    const IdlType* type = nullptr;
    const IdlStruct* structure = nullptr;
    const IdlEnum* enumeration = nullptr;
};

Resolved resolve(const TypeLibrary& types, const IdlType& type) {
    const IdlType* current = &type;
    for (int hops = 0; hops < MAX_DEPTH; ++hops) {
        if (current->kind != Kind::named)
            return current->kind == Kind::unsupported ? Resolved{} : Resolved{current, nullptr, nullptr};
        const IdlDeclaration* declared = types.resolve(current->name, current->scope);
        if (declared == nullptr)
            return {};
        if (const auto* structure = std::get_if<IdlStruct>(declared))
            return {nullptr, structure, nullptr};
        if (const auto* enumeration = std::get_if<IdlEnum>(declared))
            return {nullptr, nullptr, enumeration};
        const auto* alias = std::get_if<IdlTypedef>(declared);
        if (alias == nullptr)
            return {};
        current = &alias->type;
    }
    return {};
}

std::size_t enum_size(const IdlEnum& type) {
    return type.bit_bound <= 8 ? 1 : type.bit_bound <= 16 ? 2 : 4;
}

/// The key's largest size in bytes from `offset` on, nullopt when it has none (a string or a sequence: Cyclone
/// DDS takes even a bounded one as a key of no fixed size). Sets `ok` false on a type it cannot serialize.
std::optional<std::size_t> max_size(const TypeLibrary& types, const IdlType& type, std::size_t offset, bool xcdr2,
                                    bool& ok, int depth);

std::optional<std::size_t> max_key_size(const TypeLibrary& types, const IdlStruct& type, std::size_t offset, bool xcdr2,
                                        bool& ok, int depth) {
    if (depth > MAX_DEPTH) {
        ok = false;
        return std::nullopt;
    }
    std::vector<const IdlMember*> members;
    members_of(types, type, members);
    // Every key member is looked at, for `ok`, even once the size has no bound.
    std::size_t end = offset;
    bool bounded = true;
    for (const std::size_t position : key_positions(members)) {
        const auto next = max_size(types, members[position]->type, end, xcdr2, ok, depth + 1);
        if (!ok)
            return std::nullopt;
        bounded = bounded && next.has_value();
        end = next.value_or(end);
    }
    return bounded ? std::optional<std::size_t>(end) : std::nullopt;
}

std::optional<std::size_t> max_size(const TypeLibrary& types, const IdlType& type, std::size_t offset, bool xcdr2,
                                    bool& ok, int depth) {
    const Resolved resolved = resolve(types, type);
    if (resolved.structure)
        return max_key_size(types, *resolved.structure, offset, xcdr2, ok, depth);
    if (resolved.enumeration) {
        const std::size_t size = enum_size(*resolved.enumeration);
        return aligned(offset, size, xcdr2) + size;
    }
    if (resolved.type == nullptr) {
        ok = false;
        return std::nullopt;
    }
    const IdlType& expression = *resolved.type;
    if (const std::size_t size = expression.primitive_size())
        return aligned(offset, size, xcdr2) + size;
    if (expression.kind == Kind::array) {
        std::size_t count = 1;
        for (const std::uint32_t dimension : expression.dimensions)
            count *= dimension;
        std::optional<std::size_t> end = offset;
        for (std::size_t i = 0; i < count && end; ++i)
            end = max_size(types, *expression.element, *end, xcdr2, ok, depth + 1);
        return ok ? end : std::nullopt;
    }
    // Strings and sequences: no fixed size.
    return std::nullopt;
}

/// Big-endian CDR of the key, alignment from its first byte.
class KeyWriter {
  public:
    KeyWriter(const TypeLibrary& types, bool xcdr2) : types_(types), xcdr2_(xcdr2) {}

    bool structure(const IdlStruct& type, const DecodedValue& record, int depth) {
        if (depth > MAX_DEPTH || record.kind != DecodedValue::Kind::record)
            return false;
        std::vector<const IdlMember*> members;
        members_of(types_, type, members);
        for (const std::size_t position : key_positions(members)) {
            // An appendable struct of an older version may end before its key: no key then.
            if (position >= record.fields.size() ||
                !value(members[position]->type, record.fields[position].second, depth))
                return false;
        }
        return true;
    }

    const std::vector<std::uint8_t>& bytes() const { return bytes_; }

  private:
    bool value(const IdlType& type, const DecodedValue& decoded, int depth) {
        const Resolved resolved = resolve(types_, type);
        if (resolved.structure)
            return structure(*resolved.structure, decoded, depth + 1);
        if (resolved.enumeration) {
            put(static_cast<std::uint64_t>(decoded.signed_integer), enum_size(*resolved.enumeration));
            return true;
        }
        if (resolved.type == nullptr)
            return false;
        const IdlType& expression = *resolved.type;
        switch (expression.kind) {
            case Kind::string: {
                const std::string& text = decoded.text;
                put(text.size() + 1, 4);
                bytes_.insert(bytes_.end(), text.begin(), text.end());
                bytes_.push_back(0);
                return true;
            }
            case Kind::sequence:
                put(decoded.items.size(), 4);
                return elements(*expression.element, decoded, depth);
            case Kind::array:
                return array(expression, 0, decoded, depth);
            default:
                return primitive(expression, decoded);
        }
    }

    bool array(const IdlType& type, std::size_t dimension, const DecodedValue& decoded, int depth) {
        if (dimension + 1 == type.dimensions.size())
            return elements(*type.element, decoded, depth);
        for (const DecodedValue& item : decoded.items) {
            if (!array(type, dimension + 1, item, depth))
                return false;
        }
        return true;
    }

    bool elements(const IdlType& element, const DecodedValue& list, int depth) {
        for (const DecodedValue& item : list.items) {
            if (!value(element, item, depth + 1))
                return false;
        }
        return true;
    }

    bool primitive(const IdlType& type, const DecodedValue& decoded) {
        const std::size_t size = type.primitive_size();
        std::uint64_t raw = 0;
        switch (decoded.kind) {
            case DecodedValue::Kind::boolean:
                raw = decoded.boolean ? 1 : 0;
                break;
            case DecodedValue::Kind::character:
                raw = decoded.text.empty() ? 0 : static_cast<std::uint8_t>(decoded.text[0]);
                break;
            case DecodedValue::Kind::unsigned_integer:
                raw = decoded.unsigned_integer;
                break;
            case DecodedValue::Kind::signed_integer:
                raw = static_cast<std::uint64_t>(decoded.signed_integer);
                break;
            case DecodedValue::Kind::real:
                if (size == 4) {
                    const float single = static_cast<float>(decoded.real);
                    std::uint32_t bits = 0;
                    std::memcpy(&bits, &single, sizeof bits);
                    raw = bits;
                } else {
                    std::memcpy(&raw, &decoded.real, sizeof raw);
                }
                break;
            default:
                return false;
        }
        put(raw, size);
        return true;
    }

    /// The low `size` bytes of `value`, most significant first, after the padding its alignment needs.
    void put(std::uint64_t value, std::size_t size) {
        bytes_.resize(aligned(bytes_.size(), size, xcdr2_), 0);
        for (std::size_t i = size; i-- > 0;)
            bytes_.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
    }

    const TypeLibrary& types_;
    const bool xcdr2_;
    std::vector<std::uint8_t> bytes_;
};

KeyHash md5(const std::vector<std::uint8_t>& bytes) {
    KeyHash hash{};
    unsigned int length = 0;
    EVP_Digest(bytes.data(), bytes.size(), hash.data(), &length, EVP_md5(), nullptr);
    return hash;
}

}  // namespace

std::optional<KeyHasher> KeyHasher::for_type(const TypeLibrary& types, const std::string& type_name, std::string& why) {
    const IdlDeclaration* declared = types.find(type_name);
    const auto* type = declared ? std::get_if<IdlStruct>(declared) : nullptr;
    if (type == nullptr) {
        why = declared ? type_name + " is not a struct" : "no IDL for the type " + type_name;
        return std::nullopt;
    }
    std::vector<const IdlMember*> members;
    members_of(types, *type, members);
    if (std::none_of(members.begin(), members.end(), [](const IdlMember* member) { return member->key; })) {
        why = type_name + " has no @key member";
        return std::nullopt;
    }
    bool ok = true;
    const auto xcdr1_size = max_key_size(types, *type, 0, false, ok, 0);
    const auto xcdr2_size = max_key_size(types, *type, 0, true, ok, 0);
    if (!ok) {
        why = type_name + ": a key member's type cannot be serialized (unknown, or not supported)";
        return std::nullopt;
    }
    const std::vector<std::size_t> keys = key_positions(members);
    return KeyHasher(types, type_name, keys.back() + 1, !xcdr1_size || *xcdr1_size > 16,
                     !xcdr2_size || *xcdr2_size > 16);
}

std::optional<KeyHash> KeyHasher::hash(const std::uint8_t* data, std::size_t size, std::string& why) const {
    const CdrDecodeResult decoded = decode_cdr(data, size, type_name_, *types_, decoded_members_);
    if (!decoded.value) {
        why = decoded.error;
        return std::nullopt;
    }
    const bool xcdr2 = static_cast<std::uint16_t>(data[0] << 8 | data[1]) >= CDR2_BE;
    const auto* type = std::get_if<IdlStruct>(types_->find(type_name_));
    KeyWriter writer(*types_, xcdr2);
    if (!writer.structure(*type, *decoded.value, 0)) {
        why = type_name_ + ": the sample ends before its key";
        return std::nullopt;
    }
    if (xcdr2 ? md5_xcdr2_ : md5_xcdr1_)
        return md5(writer.bytes());
    KeyHash hash{};
    std::copy(writer.bytes().begin(), writer.bytes().end(), hash.begin());
    return hash;
}

}  // namespace tgw::types
