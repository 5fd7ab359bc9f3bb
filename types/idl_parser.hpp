// The IDL that robotics stacks write (ROS 2's generated .idl files, fastddsgen's and Cyclone's inputs), parsed into
// a TypeLibrary: module, struct (with inheritance), enum, typedef, integer const (for bounds), primitives,
// string<N>, sequence<T,N>, arrays, and the annotations that change the wire (@key, @optional, @id,
// @final/@appendable/@mutable/@extensibility, @bit_bound, @value). Other annotations (@topic, @verbatim, @default,
// @unit, ...) are read and ignored. union, bitset and bitmask declarations are skipped and remembered as
// unsupported; wstring, wchar, long double, map and fixed parse as unsupported member types.
#pragma once

#include <functional>
#include <string>

#include "types/idl_lexer.hpp"

namespace tgw::types {

class TypeLibrary;

/// Called with each #include of a file before its declarations are parsed, so that the included file's
/// constants are known when a bound uses them.
using IdlIncludeHandler = std::function<void(const IdlInclude&)>;

/// Parses the IDL `text` of `file` into `library`. Throws base::ConfigError "FILE:LINE: what was expected" on
/// the first error, and on a name declared twice.
void parse_idl(const std::string& text, const std::string& file, TypeLibrary& library,
               const IdlIncludeHandler& on_include = {});

}  // namespace tgw::types
