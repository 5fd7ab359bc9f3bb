// Which samples an RTPS message carries: the writer and sequence number of each DATA and DATA_FRAG. Pure bytes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace tgw::dds {

/// One sample (or some of its fragments) in a message: its writer's entity id within the sending participant and
/// its sequence number.
struct RtpsSampleRef {
    std::array<std::uint8_t, 4> writer{};
    std::int64_t sequence = 0;
    /// DATA_FRAG: the first fragment the submessage carries (from 1); 0 for DATA.
    std::uint32_t first_fragment = 0;

    bool operator==(const RtpsSampleRef& other) const {
        return writer == other.writer && sequence == other.sequence && first_fragment == other.first_fragment;
    }
};

/// Fills `out` with up to `max` of the samples `message` carries, in order; returns how many it found (at most
/// `max`). 0 for a message that is not well formed, or protected as a whole (DDS Security), whose submessages
/// cannot be read.
std::size_t rtps_sample_refs(const std::uint8_t* message, std::size_t size, RtpsSampleRef* out, std::size_t max);

}  // namespace tgw::dds
