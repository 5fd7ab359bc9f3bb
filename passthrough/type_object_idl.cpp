#include "passthrough/type_object_idl.hpp"

#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fastrtps/types/TypeIdentifier.h>
#include <fastrtps/types/TypeObject.h>

namespace tgw::passthrough {

namespace xt = eprosima::fastrtps::types;

namespace {

constexpr std::uint32_t FASTDDSGEN_STRING_BOUND = 255;

/// Why a TypeObject cannot become IDL; caught in type_object_idl().
struct Untranslatable : std::runtime_error {
    using std::runtime_error::runtime_error;
};

std::string hash_text(const xt::TypeIdentifier& id) {
    static const char digits[] = "0123456789abcdef";
    std::string text = id._d() == xt::EK_COMPLETE ? "complete hash " : "minimal hash ";
    for (std::size_t i = 0; i < 14; ++i) {  // XTypes: a 14-byte EquivalenceHash
        text += digits[id.equivalence_hash()[i] >> 4];
        text += digits[id.equivalence_hash()[i] & 0xF];
    }
    return text;
}

const char* primitive_name(xt::octet kind) {
    switch (kind) {
        case xt::TK_BOOLEAN:
            return "boolean";
        case xt::TK_BYTE:
            return "octet";
        case xt::TK_INT16:
            return "short";
        case xt::TK_INT32:
            return "long";
        case xt::TK_INT64:
            return "long long";
        case xt::TK_UINT16:
            return "unsigned short";
        case xt::TK_UINT32:
            return "unsigned long";
        case xt::TK_UINT64:
            return "unsigned long long";
        case xt::TK_FLOAT32:
            return "float";
        case xt::TK_FLOAT64:
            return "double";
        case xt::TK_CHAR8:
            return "char";
        default:
            return nullptr;
    }
}

/// "a::b::C" as its modules ("a", "b") and its own name ("C").
std::vector<std::string> split_scoped(const std::string& scoped) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t cut; (cut = scoped.find("::", start)) != std::string::npos; start = cut + 2)
        parts.push_back(scoped.substr(start, cut - start));
    parts.push_back(scoped.substr(start));
    return parts;
}

/// Writes each declaration after the ones it refers to, each once, each in its modules.
class IdlWriter {
  public:
    explicit IdlWriter(const TypeObjectLookup& lookup) : lookup_(lookup) {}

    /// Declares the type `object` describes, as `name` or, when that is empty, under the name it has in `object`;
    /// the name declared.
    std::string declare(const xt::TypeObject& object, const std::string& name = {}) {
        if (object._d() != xt::EK_COMPLETE)
            throw Untranslatable("a minimal TypeObject names no members");
        const xt::CompleteTypeObject& complete = object.complete();
        switch (complete._d()) {
            case xt::TK_STRUCTURE:
                return declare_struct(complete.struct_type(), or_own(name, complete.struct_type().header()));
            case xt::TK_ENUM:
                return declare_enum(complete.enumerated_type(), or_own(name, complete.enumerated_type().header()));
            case xt::TK_ALIAS:
                return declare_alias(complete.alias_type(), or_own(name, complete.alias_type().header()));
            case xt::TK_UNION:
                throw Untranslatable("unions are not decoded");
            case xt::TK_BITMASK:
                throw Untranslatable("bitmasks are not decoded");
            case xt::TK_BITSET:
                throw Untranslatable("bitsets are not decoded");
            default:
                throw Untranslatable("a TypeObject of kind " + std::to_string(complete._d()) + " is not decoded");
        }
    }

    std::string text() const { return text_.str(); }

  private:
    /// The type specification of `id`, and in `dimensions` the "[N]..." an array puts after the declarator.
    std::string type_spec(const xt::TypeIdentifier& id, std::string& dimensions) {
        if (const char* primitive = primitive_name(id._d()))
            return primitive;
        switch (id._d()) {
            case xt::TI_STRING8_SMALL:
                // fastddsgen 2.3 announces every unbounded string as string<255>: a bound that cannot be told from
                // a real one is not checked, so that a longer string still decodes.
                return bounded("string",
                               id.string_sdefn().bound() == FASTDDSGEN_STRING_BOUND ? 0 : id.string_sdefn().bound());
            case xt::TI_STRING8_LARGE:
                return bounded("string", id.string_ldefn().bound());
            case xt::TI_PLAIN_SEQUENCE_SMALL:
                return sequence(*id.seq_sdefn().element_identifier(), id.seq_sdefn().bound());
            case xt::TI_PLAIN_SEQUENCE_LARGE:
                return sequence(*id.seq_ldefn().element_identifier(), id.seq_ldefn().bound());
            case xt::TI_PLAIN_ARRAY_SMALL:
                return array(*id.array_sdefn().element_identifier(), id.array_sdefn().array_bound_seq(), dimensions);
            case xt::TI_PLAIN_ARRAY_LARGE:
                return array(*id.array_ldefn().element_identifier(), id.array_ldefn().array_bound_seq(), dimensions);
            case xt::EK_COMPLETE:
            case xt::EK_MINIMAL: {
                const xt::TypeObject* referred = lookup_ ? lookup_(id) : nullptr;
                if (referred == nullptr)
                    throw Untranslatable("refers to a type its publisher did not announce (" + hash_text(id) + ")");
                return "::" + declare(*referred);
            }
            case xt::TI_STRING16_SMALL:
            case xt::TI_STRING16_LARGE:
                throw Untranslatable("wide strings are not decoded");
            case xt::TI_PLAIN_MAP_SMALL:
            case xt::TI_PLAIN_MAP_LARGE:
                throw Untranslatable("maps are not decoded");
            default:
                throw Untranslatable("a type identifier of kind " + std::to_string(id._d()) + " is not decoded");
        }
    }

    static std::string bounded(const char* what, std::uint32_t bound) {
        return bound == 0 ? what : std::string(what) + "<" + std::to_string(bound) + ">";
    }

    std::string sequence(const xt::TypeIdentifier& element, std::uint32_t bound) {
        std::string dimensions;
        std::string spec = type_spec(element, dimensions);
        if (!dimensions.empty())
            throw Untranslatable("a sequence of arrays needs a typedef IDL has no name for");
        return "sequence<" + spec + (bound == 0 ? "" : ", " + std::to_string(bound)) + ">";
    }

    template <typename Bounds>
    std::string array(const xt::TypeIdentifier& element, const Bounds& bounds, std::string& dimensions) {
        for (auto bound : bounds)
            dimensions += "[" + std::to_string(bound) + "]";
        std::string inner;
        std::string spec = type_spec(element, inner);
        dimensions += inner;
        return spec;
    }

    /// Adds `declaration` (of the last part of `scoped_name`) inside the modules of `scoped_name`.
    void emit(const std::string& scoped_name, const std::string& declaration) {
        const std::vector<std::string> parts = split_scoped(scoped_name);
        for (std::size_t i = 0; i + 1 < parts.size(); ++i)
            text_ << "module " << parts[i] << " {\n";
        text_ << declaration;
        for (std::size_t i = 0; i + 1 < parts.size(); ++i)
            text_ << "};\n";
    }

    static std::string own_name(const std::string& scoped_name) { return split_scoped(scoped_name).back(); }

    template <typename Header>
    static std::string or_own(const std::string& name, const Header& header) {
        return name.empty() ? header.detail().type_name() : name;
    }

    /// False when `name` was declared already (a type two members use).
    bool first_time(const std::string& name) { return declared_.insert(name).second; }

    std::string declare_struct(const xt::CompleteStructType& type, const std::string& name) {
        if (!first_time(name))
            return name;
        // Members' types first: each declaration before its first use, as IDL and other readers of it want.
        std::string base;
        if (type.header().base_type()._d() != 0) {
            std::string dimensions;
            base = type_spec(type.header().base_type(), dimensions);
        }
        const bool is_mutable = type.struct_flags().IS_MUTABLE();
        std::ostringstream members;
        for (const xt::CompleteStructMember& member : type.member_seq()) {
            const std::string& member_name = member.detail().name();
            std::string dimensions;
            std::string spec;
            try {
                spec = type_spec(member.common().member_type_id(), dimensions);
            } catch (const Untranslatable& e) {
                throw Untranslatable("member '" + member_name + "' of " + name + ": " + e.what());
            }
            members << "    ";
            if (member.common().member_flags().IS_KEY())
                members << "@key ";
            if (member.common().member_flags().IS_OPTIONAL())
                members << "@optional ";
            if (is_mutable)
                members << "@id(" << member.common().member_id() << ") ";
            members << spec << " " << member_name << dimensions << ";\n";
        }
        std::ostringstream out;
        if (type.struct_flags().IS_FINAL())
            out << "@final\n";
        else if (is_mutable)
            out << "@mutable\n";
        else if (type.struct_flags().IS_APPENDABLE())
            out << "@appendable\n";
        out << "struct " << own_name(name) << (base.empty() ? "" : " : " + base) << " {\n" << members.str() << "};\n";
        emit(name, out.str());
        return name;
    }

    std::string declare_enum(const xt::CompleteEnumeratedType& type, const std::string& name) {
        if (!first_time(name))
            return name;
        std::ostringstream out;
        const auto bit_bound = type.header().common().bit_bound();
        if (bit_bound != 0 && bit_bound != 32)
            out << "@bit_bound(" << bit_bound << ")\n";
        out << "enum " << own_name(name) << " {\n";
        const auto& literals = type.literal_seq();
        for (std::size_t i = 0; i < literals.size(); ++i) {
            out << "    @value(" << literals[i].common().value() << ") " << literals[i].detail().name()
                << (i + 1 < literals.size() ? ",\n" : "\n");
        }
        out << "};\n";
        emit(name, out.str());
        return name;
    }

    std::string declare_alias(const xt::CompleteAliasType& type, const std::string& name) {
        if (!first_time(name))
            return name;
        std::string dimensions;
        std::string spec = type_spec(type.body().common().related_type(), dimensions);
        emit(name, "typedef " + spec + " " + own_name(name) + dimensions + ";\n");
        return name;
    }

    const TypeObjectLookup& lookup_;
    std::set<std::string> declared_;
    std::ostringstream text_;
};

}  // namespace

TypeObjectIdl type_object_idl(const xt::TypeObject& object, const std::string& type_name,
                              const TypeObjectLookup& lookup) {
    TypeObjectIdl result;
    IdlWriter writer(lookup);
    try {
        writer.declare(object, type_name);
        result.text = writer.text();
    } catch (const Untranslatable& e) {
        result.missing = e.what();
    }
    return result;
}

}  // namespace tgw::passthrough
