#include "compact/zstd_frame.hpp"

#include <zstd.h>

namespace tgw::compact {

namespace {

/// Fast, and within a few per cent of the higher levels on the few hundred bytes of a bundle or a status.
constexpr int ZSTD_LEVEL = 3;

}  // namespace

bool zstd_frame(const std::uint8_t* raw, std::size_t size, std::vector<std::uint8_t>& out) {
    const std::size_t prefix = out.size();
    out.resize(prefix + ZSTD_compressBound(size));
    const std::size_t frame = ZSTD_compress(out.data() + prefix, out.size() - prefix, raw, size, ZSTD_LEVEL);
    out.resize(ZSTD_isError(frame) ? prefix : prefix + frame);
    return !ZSTD_isError(frame);
}

FrameError unzstd_frame(const std::uint8_t* bytes, std::size_t size, std::size_t max_bytes,
                        std::vector<std::uint8_t>& raw) {
    // Exactly one frame, whose header declares its content size: nothing is decompressed before that is known.
    const std::size_t frame_bytes = ZSTD_findFrameCompressedSize(bytes, size);
    if (ZSTD_isError(frame_bytes) || frame_bytes != size)
        return FrameError::malformed;
    const unsigned long long content = ZSTD_getFrameContentSize(bytes, size);
    if (content == ZSTD_CONTENTSIZE_ERROR || content == ZSTD_CONTENTSIZE_UNKNOWN)
        return FrameError::malformed;
    if (content > max_bytes)
        return FrameError::too_large;
    raw.resize(static_cast<std::size_t>(content));
    const std::size_t written = ZSTD_decompress(raw.data(), raw.size(), bytes, size);
    if (ZSTD_isError(written) || written != raw.size())
        return FrameError::malformed;
    return FrameError::none;
}

}  // namespace tgw::compact
