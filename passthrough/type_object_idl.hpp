// IDL text for the XTypes TypeObject a publisher announces in discovery, so that tm-basecamp can decode a type it
// was given no IDL for with the parser and decoder it has for IDL files, and the gateway can tell a TypeObject
// that describes its type by itself (worth passing on) from one that does not.
//
// A Fast DDS writer whose type has a TypeObject (fastddsgen -typeobject and its register...Types(), or a
// DynamicType) sends the complete TypeObject of its top-level type with its publication. The types that one
// refers to (a nested struct, an enum, a typedef) travel by hash only: `lookup` finds those it can, and they are
// declared under the names their own TypeObjects give.
#pragma once

#include <functional>
#include <string>

namespace eprosima::fastrtps::types {
class TypeIdentifier;
class TypeObject;
}  // namespace eprosima::fastrtps::types

namespace tgw::passthrough {

/// The complete TypeObject for a type referred to by hash; nullptr when it is not known.
using TypeObjectLookup =
    std::function<const eprosima::fastrtps::types::TypeObject*(const eprosima::fastrtps::types::TypeIdentifier&)>;

/// What type_object_idl() made of a TypeObject.
struct TypeObjectIdl {
    std::string text;     ///< IDL declaring it and every type it refers to, each before its first use
    std::string missing;  ///< why there is no text ("member 'pose' refers to a type ... not announced"); else empty

    bool ok() const { return missing.empty(); }
};

/// The IDL of the type a complete TypeObject describes (a struct, an enum or a typedef), declared as `type_name`:
/// the name its writer announced, which fastddsgen's TypeObjects give without their modules. Members keep their key,
/// optional and extensibility annotations, and their ids where the struct is mutable. Fails, saying why, on a
/// minimal TypeObject (it has no names), a referenced type `lookup` does not know, or what IDL cannot say without
/// declarations of its own (a sequence of arrays) or the decoder does not read (unions, maps, wide strings).
TypeObjectIdl type_object_idl(const eprosima::fastrtps::types::TypeObject& object, const std::string& type_name,
                              const TypeObjectLookup& lookup);

}  // namespace tgw::passthrough
