// The paper's sample type (idl/PaperWorkload.idl) as the reports read it from a recording or an on-robot log:
// serialized, its sequence number at a fixed offset.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

namespace tgw::basecamp {

/// The type name its samples are recorded and logged under.
inline constexpr const char* PAPER_MESSAGE_TYPE = "tgw::idl::PaperMessage";

/// Sequence number of a serialized tgw::idl::PaperMessage (encapsulation, generated_ns, sequence, data),
/// or nothing when the payload is too short or not CDR.
std::optional<std::uint32_t> paper_message_sequence(const std::uint8_t* payload, std::size_t size);

}  // namespace tgw::basecamp
