// One zstd frame around a byte string, and back, with the decompressed size bounded before anything is
// decompressed: what the compact WAN mode compresses (a bundle's entries, the gateway's status) comes off a
// network, and a frame that claims a gigabyte must cost nothing but its refusal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tgw::compact {

/// Appends one zstd frame of `raw` to `out` (its content size in the frame's header). False, `out` as it was, if
/// zstd failed.
bool zstd_frame(const std::uint8_t* raw, std::size_t size, std::vector<std::uint8_t>& out);

enum class FrameError { none, malformed, too_large };

/// Replaces `raw` with what `bytes` decompress to, when `bytes` are exactly one zstd frame whose header declares
/// a content size of at most `max_bytes`.
FrameError unzstd_frame(const std::uint8_t* bytes, std::size_t size, std::size_t max_bytes,
                        std::vector<std::uint8_t>& raw);

}  // namespace tgw::compact
