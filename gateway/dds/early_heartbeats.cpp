#include "gateway/dds/early_heartbeats.hpp"

#include <cstring>

#include "wire/rtps_submessage.hpp"

namespace tgw::dds {

namespace {

using namespace wire::rtps_bytes;

/// Whether the DATA_FRAG's fragments end before its sample does.
bool ends_early(const std::uint8_t* body, bool le) {
    const std::uint64_t first = read_u32(body + FRAGMENT_START_OFFSET, le);
    const std::uint64_t count = read_u16(body + FRAGMENT_START_OFFSET + 4, le);
    const std::uint64_t fragment_size = read_u16(body + FRAGMENT_START_OFFSET + 6, le);
    const std::uint64_t sample_size = read_u32(body + FRAGMENT_START_OFFSET + 8, le);
    return first >= 1 && (first - 1 + count) * fragment_size < sample_size;
}

}  // namespace

bool without_early_heartbeats(const std::uint8_t* message, std::size_t size, std::vector<std::uint8_t>& out) {
    if (size < MESSAGE_HEADER_BYTES || std::memcmp(message, "RTPS", 4) != 0) {
        return false;
    }
    bool early_fragment = false;
    bool heartbeat = false;
    std::size_t pos = MESSAGE_HEADER_BYTES;
    while (pos < size) {
        if (size - pos < SUBMESSAGE_HEADER_BYTES) {
            return false;
        }
        const std::uint8_t* sub = message + pos;
        const std::size_t length = octets_to_next_header(sub);
        if (sub[0] == SRTPS_PREFIX || sub[0] == SEC_PREFIX || pos + SUBMESSAGE_HEADER_BYTES + length > size ||
            length == 0) {
            return false;  // protected, not well formed, or a last submessage that runs to the end: left alone
        }
        if (sub[0] == DATA_FRAG && length >= DATA_FRAG_FIELDS_BYTES) {
            early_fragment =
                early_fragment || ends_early(sub + SUBMESSAGE_HEADER_BYTES, (sub[1] & FLAG_LITTLE_ENDIAN) != 0);
        }
        heartbeat = heartbeat || sub[0] == HEARTBEAT;
        pos += SUBMESSAGE_HEADER_BYTES + ((length + 3) & ~std::size_t{3});
    }
    if (!early_fragment || !heartbeat || pos != size) {
        return false;
    }
    out.assign(message, message + MESSAGE_HEADER_BYTES);
    for (pos = MESSAGE_HEADER_BYTES; pos < size;) {
        const std::uint8_t* sub = message + pos;
        const std::size_t next = pos + SUBMESSAGE_HEADER_BYTES + ((octets_to_next_header(sub) + 3) & ~std::size_t{3});
        if (sub[0] != HEARTBEAT) {
            out.insert(out.end(), sub, message + next);
        }
        pos = next;
    }
    return true;
}

}  // namespace tgw::dds
