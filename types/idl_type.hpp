// The types an IDL file declares, as the programs need them to handle samples of types they were never compiled
// with: structs, enums, typedefs and the type expressions of their members. Names in member types stay as
// written, with the scope they were written in, and are resolved when a sample is decoded (TypeLibrary::resolve),
// so that files may come in any order.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace tgw::types {

/// Where a declaration or a type reference was written: for error messages.
struct IdlLocation {
    std::string file;
    int line = 0;

    std::string text() const { return file + ":" + std::to_string(line); }
};

/// A type as written in a member, typedef or sequence: a primitive, string<N>, sequence<T,N>, an array of a
/// declarator (T x[N][M]), or a name to resolve.
struct IdlType {
    enum class Kind {
        boolean,
        char8,
        octet,
        int8,
        uint8,
        int16,
        uint16,
        int32,
        uint32,
        int64,
        uint64,
        float32,
        float64,
        string,
        sequence,
        array,
        named,        ///< a struct, enum or typedef: `name` as written, resolved in `scope`
        unsupported,  ///< parsed but not decodable (wstring, wchar, long double, map, fixed): `name` says which
    };

    Kind kind = Kind::int32;
    std::uint32_t bound = 0;                 ///< string and sequence: the bound, 0 for unbounded
    std::vector<std::uint32_t> dimensions;   ///< array: each dimension, outermost first
    std::shared_ptr<const IdlType> element;  ///< sequence and array: the element type
    std::string name;                        ///< named: as written ("Header", "::std_msgs::msg::Header")
    std::string scope;                       ///< named: the module it was written in ("geometry_msgs::msg")
    IdlLocation where;

    /// Bytes of a primitive on the wire (1, 2, 4 or 8); 0 for every other kind.
    std::size_t primitive_size() const;
};

/// The member of a struct, from one declarator: `@key long a, b[3];` makes two members.
struct IdlMember {
    std::string name;
    IdlType type;
    bool key = false;
    bool optional = false;
    std::optional<std::uint32_t> id;  ///< @id(N)
};

/// How a struct may evolve (XTypes): decides whether XCDR2 puts a DHEADER before it.
enum class IdlExtensibility { unspecified, final, appendable, mutable_ };

/// A struct: its members in declaration order, after its base's.
struct IdlStruct {
    std::string name;             ///< fully scoped, as DDS type names use it: "tgw::idl::GatewayStatus"
    std::optional<IdlType> base;  ///< the struct it inherits from (a named type)
    std::vector<IdlMember> members;
    IdlExtensibility extensibility = IdlExtensibility::unspecified;
    bool topic = false;  ///< @topic
    IdlLocation where;
};

/// One literal of an enum and its value (@value, or one more than the literal before).
struct IdlEnumerator {
    std::string name;
    std::int32_t value = 0;
};

/// An enum: on the wire, the value of one of its literals.
struct IdlEnum {
    std::string name;
    std::vector<IdlEnumerator> enumerators;
    std::uint32_t bit_bound = 32;  ///< @bit_bound: the wire holds 1, 2 or 4 bytes
    IdlLocation where;
};

/// Another name for a type, arrays of the declarator included (`typedef double Vec3[3];`).
struct IdlTypedef {
    std::string name;
    IdlType type;
    IdlLocation where;
};

/// A declaration the parser skips but remembers, so that a member of its type says why it cannot be decoded.
struct IdlUnsupported {
    std::string name;
    std::string what;  ///< "union", "bitset", "bitmask"
    IdlLocation where;
};

/// What a fully scoped name declares.
using IdlDeclaration = std::variant<IdlStruct, IdlEnum, IdlTypedef, IdlUnsupported>;

/// The fully scoped name of a declaration.
const std::string& declaration_name(const IdlDeclaration& declaration);
/// Where a declaration was written.
const IdlLocation& declaration_location(const IdlDeclaration& declaration);

}  // namespace tgw::types
