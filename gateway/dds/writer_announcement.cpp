#include "gateway/dds/writer_announcement.hpp"

#include <cstring>

#include "wire/rtps_submessage.hpp"

namespace tgw::dds {

namespace {

using namespace wire::rtps_bytes;

constexpr std::uint8_t FLAG_INLINE_QOS = 0x02;
constexpr std::uint8_t FLAG_DATA = 0x04;
constexpr std::uint16_t PID_SENTINEL = 0x0001;
constexpr std::uint16_t PID_TOPIC_NAME = 0x0005;
constexpr std::size_t ENCAPSULATION_BYTES = 4;
/// PL_CDR_BE and PL_CDR_LE (DDSI-RTPS 10.5): the second byte of the encapsulation kind.
constexpr std::uint8_t PL_CDR_BE = 0x02;
constexpr std::uint8_t PL_CDR_LE = 0x03;

/// Skips a parameter list at `p` (up to `end`) through its PID_SENTINEL; nullptr if it does not read.
const std::uint8_t* skip_parameter_list(const std::uint8_t* p, const std::uint8_t* end, bool little_endian) {
    while (end - p >= 4) {
        const std::uint16_t pid = read_u16(p, little_endian);
        const std::uint16_t length = read_u16(p + 2, little_endian);
        p += 4;
        if (pid == PID_SENTINEL) {
            return p;
        }
        if (end - p < length) {
            return nullptr;
        }
        p += length;
    }
    return nullptr;
}

/// PID_TOPIC_NAME's string in the serialized payload [p, end).
std::optional<std::string_view> topic_name(const std::uint8_t* p, const std::uint8_t* end) {
    if (end - p < static_cast<std::ptrdiff_t>(ENCAPSULATION_BYTES) || p[0] != 0x00 ||
        (p[1] != PL_CDR_BE && p[1] != PL_CDR_LE)) {
        return std::nullopt;
    }
    const bool little_endian = p[1] == PL_CDR_LE;
    p += ENCAPSULATION_BYTES;
    while (end - p >= 4) {
        const std::uint16_t pid = read_u16(p, little_endian) & 0x3fff;  // without the vendor and must-understand bits
        const std::uint16_t length = read_u16(p + 2, little_endian);
        p += 4;
        if (pid == PID_SENTINEL || end - p < length) {
            return std::nullopt;
        }
        if (pid == PID_TOPIC_NAME) {
            if (length < 4) {
                return std::nullopt;
            }
            const std::uint32_t chars = read_u32(p, little_endian);  // with its terminating NUL
            if (chars == 0 || chars > static_cast<std::uint32_t>(length - 4) || p[4 + chars - 1] != 0) {
                return std::nullopt;
            }
            return std::string_view(reinterpret_cast<const char*>(p + 4), chars - 1);
        }
        p += length;
    }
    return std::nullopt;
}

}  // namespace

std::optional<WriterAnnouncements> writer_announcements(const std::uint8_t* message, std::size_t size) {
    if (size < MESSAGE_HEADER_BYTES || std::memcmp(message, "RTPS", 4) != 0) {
        return std::nullopt;
    }
    WriterAnnouncements found;
    std::size_t pos = MESSAGE_HEADER_BYTES;
    while (pos + SUBMESSAGE_HEADER_BYTES <= size) {
        const std::uint8_t* sub = message + pos;
        const bool little_endian = (sub[1] & FLAG_LITTLE_ENDIAN) != 0;
        const std::size_t declared = octets_to_next_header(sub);
        const std::size_t length = declared == 0 ? size - pos - SUBMESSAGE_HEADER_BYTES : declared;
        if (pos + SUBMESSAGE_HEADER_BYTES + length > size) {
            return std::nullopt;
        }
        const std::uint8_t* body = sub + SUBMESSAGE_HEADER_BYTES;
        switch (sub[0]) {
            case INFO_DST:
            case INFO_TS:
            case HEARTBEAT:
            case EPROSIMA_STATISTICS:
                break;
            case DATA: {
                if (found.count == found.topics.size() || length < DATA_FIELDS_BYTES || (sub[1] & FLAG_DATA) == 0 ||
                    std::memcmp(body + SAMPLE_WRITER_ID_OFFSET, SEDP_PUBLICATIONS_WRITER_ID, 4) != 0) {
                    return std::nullopt;
                }
                const std::uint8_t* end = body + length;
                const std::uint8_t* p = body + 4 + read_u16(body + 2, little_endian);  // octetsToInlineQos
                if (p > end) {
                    return std::nullopt;
                }
                if ((sub[1] & FLAG_INLINE_QOS) != 0 && (p = skip_parameter_list(p, end, little_endian)) == nullptr) {
                    return std::nullopt;
                }
                const std::optional<std::string_view> topic = topic_name(p, end);
                if (!topic) {
                    return std::nullopt;
                }
                if (found.count == 0) {
                    std::memcpy(found.first.writer.data(), body + SAMPLE_WRITER_ID_OFFSET, 4);
                    const auto high = static_cast<std::int32_t>(read_u32(body + SAMPLE_SEQUENCE_OFFSET, little_endian));
                    found.first.sequence = static_cast<std::int64_t>(high) * (std::int64_t{1} << 32) +
                                           read_u32(body + SAMPLE_SEQUENCE_OFFSET + 4, little_endian);
                }
                found.topics[found.count++] = *topic;
                break;
            }
            default:
                return std::nullopt;
        }
        if (declared == 0) {
            break;
        }
        pos += SUBMESSAGE_HEADER_BYTES + length;
    }
    return found.count > 0 ? std::optional(found) : std::nullopt;
}

}  // namespace tgw::dds
