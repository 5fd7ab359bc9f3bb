// RTPS 2.x message layout (DDSI-RTPS 9.4) that the WAN transport's byte-level pieces read: submessage ids and
// headers. Pure bytes: no Fast DDS header.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tgw::wire::rtps_bytes {

constexpr std::size_t MESSAGE_HEADER_BYTES = 20;
constexpr std::size_t SUBMESSAGE_HEADER_BYTES = 4;
constexpr std::size_t GUID_PREFIX_BYTES = 12;

// Submessage ids (DDSI-RTPS 9.4.5.1.1).
constexpr std::uint8_t PAD = 0x01;
constexpr std::uint8_t ACKNACK = 0x06;
constexpr std::uint8_t HEARTBEAT = 0x07;
constexpr std::uint8_t GAP = 0x08;
constexpr std::uint8_t INFO_TS = 0x09;
constexpr std::uint8_t DATA = 0x15;
constexpr std::uint8_t DATA_FRAG = 0x16;
constexpr std::uint8_t INFO_SRC = 0x0c;
constexpr std::uint8_t INFO_REPLY_IP4 = 0x0d;
constexpr std::uint8_t INFO_DST = 0x0e;
constexpr std::uint8_t INFO_REPLY = 0x0f;
/// DDS Security 1.1, 7.3.7: a submessage protected on its own is SEC_PREFIX, SEC_BODY (its encrypted bytes),
/// SEC_POSTFIX.
constexpr std::uint8_t SEC_PREFIX = 0x31;
constexpr std::uint8_t SEC_POSTFIX = 0x32;
/// DDS Security 1.1, 7.3.7: the prefix of an RTPS message protected as a whole (rtps_protection_kind SIGN or
/// ENCRYPT). Its SRTPS_POSTFIX closes it; a receiver decodes the protected message and ignores what follows.
constexpr std::uint8_t SRTPS_PREFIX = 0x33;
/// eProsima's vendor-specific network-statistics submessage, which Debian's Fast DDS (built with statistics)
/// ends every message with.
constexpr std::uint8_t EPROSIMA_STATISTICS = 0x80;

constexpr std::uint8_t FLAG_LITTLE_ENDIAN = 0x01;

/// ENTITYID_SPDP_BUILTIN_RTPSParticipant_WRITER (DDSI-RTPS 9.3.1.5): its DATA announce the participant.
constexpr std::uint8_t SPDP_WRITER_ID[4] = {0x00, 0x01, 0x00, 0xc2};

// The fields DATA and DATA_FRAG start with (DDSI-RTPS 9.4.5.3, 9.4.5.4), as offsets into the body: extraFlags (2),
// octetsToInlineQos (2), readerId (4), writerId (4), writerSN (8: high, then low); then for DATA_FRAG
// fragmentStartingNum (4), fragmentsInSubmessage (2), fragmentSize (2), sampleSize (4).
constexpr std::size_t SAMPLE_WRITER_ID_OFFSET = 8;
constexpr std::size_t SAMPLE_SEQUENCE_OFFSET = 12;
constexpr std::size_t FRAGMENT_START_OFFSET = 20;
constexpr std::size_t DATA_FIELDS_BYTES = 20;
constexpr std::size_t DATA_FRAG_FIELDS_BYTES = 32;

/// An entity id's last byte, its kind (DDSI-RTPS 9.3.1.2): the two top bits set for the built-in endpoints
/// (discovery, liveliness, security), clear for an application's.
constexpr std::uint8_t BUILTIN_ENTITY_KIND_BITS = 0xc0;

/// A 32-bit and a 16-bit field of a submessage, in the endianness its E flag gives.
inline std::uint32_t read_u32(const std::uint8_t* p, bool little_endian) {
    return little_endian ? (static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
                            static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24)
                         : (static_cast<std::uint32_t>(p[3]) | static_cast<std::uint32_t>(p[2]) << 8 |
                            static_cast<std::uint32_t>(p[1]) << 16 | static_cast<std::uint32_t>(p[0]) << 24);
}
inline std::uint16_t read_u16(const std::uint8_t* p, bool little_endian) {
    return static_cast<std::uint16_t>(little_endian ? (p[0] | p[1] << 8) : (p[1] | p[0] << 8));
}

/// A submessage's octetsToNextHeader, in the endianness its E flag gives.
inline std::size_t octets_to_next_header(const std::uint8_t* submessage) {
    const auto lo = static_cast<std::size_t>(submessage[2]);
    const auto hi = static_cast<std::size_t>(submessage[3]);
    return (submessage[1] & FLAG_LITTLE_ENDIAN) != 0 ? (lo | (hi << 8)) : ((lo << 8) | hi);
}

}  // namespace tgw::wire::rtps_bytes
