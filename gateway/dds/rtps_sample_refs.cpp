#include "gateway/dds/rtps_sample_refs.hpp"

#include <cstring>

#include "wire/rtps_submessage.hpp"

namespace tgw::dds {

using namespace wire::rtps_bytes;

std::size_t rtps_sample_refs(const std::uint8_t* message, std::size_t size, RtpsSampleRef* out, std::size_t max) {
    if (size < MESSAGE_HEADER_BYTES || std::memcmp(message, "RTPS", 4) != 0) {
        return 0;
    }
    std::size_t found = 0;
    std::size_t pos = MESSAGE_HEADER_BYTES;
    while (pos + SUBMESSAGE_HEADER_BYTES <= size && found < max) {
        const std::uint8_t* sub = message + pos;
        const std::uint8_t id = sub[0];
        const std::size_t length = octets_to_next_header(sub);
        const std::uint8_t* body = sub + SUBMESSAGE_HEADER_BYTES;
        if (id == SRTPS_PREFIX || pos + SUBMESSAGE_HEADER_BYTES + length > size) {
            return 0;
        }
        const bool le = (sub[1] & FLAG_LITTLE_ENDIAN) != 0;
        const bool data = id == DATA && length >= DATA_FIELDS_BYTES;
        const bool data_frag = id == DATA_FRAG && length >= DATA_FRAG_FIELDS_BYTES;
        if (data || data_frag) {
            RtpsSampleRef& ref = out[found++];
            std::memcpy(ref.writer.data(), body + SAMPLE_WRITER_ID_OFFSET, ref.writer.size());
            const std::uint64_t high = read_u32(body + SAMPLE_SEQUENCE_OFFSET, le);
            ref.sequence = static_cast<std::int64_t>(high << 32 | read_u32(body + SAMPLE_SEQUENCE_OFFSET + 4, le));
            ref.first_fragment = data_frag ? read_u32(body + FRAGMENT_START_OFFSET, le) : 0;
        }
        if (length == 0) {
            break;  // runs to the end of the message (a sample's last submessage may)
        }
        pos += SUBMESSAGE_HEADER_BYTES + ((length + 3) & ~std::size_t{3});
    }
    return found;
}

}  // namespace tgw::dds
