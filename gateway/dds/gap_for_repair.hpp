// What the WAN transport sends instead of a repair of samples past their deadlines: a GAP. Pure bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tgw::dds {

/// Fills `out` with a message that tells a reliable reader to stop waiting for the samples `message` carries (the
/// DATA and DATA_FRAG of a repair): `message`'s header and INFO_DST, then a GAP (DDSI-RTPS 9.4.5.5) for each
/// reader, writer and sequence number, little endian. False, `out` untouched, when `message` carries no sample or
/// cannot be read (a message protected as a whole).
bool gap_for_repair(const std::uint8_t* message, std::size_t size, std::vector<std::uint8_t>& out);

}  // namespace tgw::dds
