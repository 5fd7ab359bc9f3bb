// A decoded sample as readable text, field by field, the way `ros2 topic echo` shows a message (YAML).
#pragma once

#include <cstddef>
#include <ostream>

#include "types/decoded_value.hpp"

namespace tgw::basecamp {

/// Writes the record `value` one member a line (`name: value`), nested structs indented by two, lists of structs
/// as YAML block items (`- name: ...`), lists of scalars on one line (`[1, 2, 3]`) cut after
/// `max_list_items` with a last item saying how many more. Strings are double-quoted (JSON escapes, valid YAML).
void write_text(std::ostream& out, const types::DecodedValue& value, std::size_t max_list_items = 64);

}  // namespace tgw::basecamp
