#include "types/idl_type.hpp"

namespace tgw::types {

std::size_t IdlType::primitive_size() const {
    switch (kind) {
        case Kind::boolean:
        case Kind::char8:
        case Kind::octet:
        case Kind::int8:
        case Kind::uint8:
            return 1;
        case Kind::int16:
        case Kind::uint16:
            return 2;
        case Kind::int32:
        case Kind::uint32:
        case Kind::float32:
            return 4;
        case Kind::int64:
        case Kind::uint64:
        case Kind::float64:
            return 8;
        case Kind::string:
        case Kind::sequence:
        case Kind::array:
        case Kind::named:
        case Kind::unsupported:
            break;
    }
    return 0;
}

const std::string& declaration_name(const IdlDeclaration& declaration) {
    return std::visit([](const auto& d) -> const std::string& { return d.name; }, declaration);
}

const IdlLocation& declaration_location(const IdlDeclaration& declaration) {
    return std::visit([](const auto& d) -> const IdlLocation& { return d.where; }, declaration);
}

}  // namespace tgw::types
