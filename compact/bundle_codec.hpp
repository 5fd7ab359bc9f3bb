// The compact WAN mode's wire format: the samples the scheduler releases together travel as one bundle, one DDS
// sample of the bundle topic, instead of one DDS sample (and its 174 bytes of headers) each.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace tgw::compact {

/// What an entry carries; the values are the wire's.
enum class EntryKind : std::uint8_t { data = 0, dispose = 1, unregister = 2 };

/// A piece of a sample too large for one bundle: bytes [offset, offset + size) of the sample's `total_bytes`.
/// The pieces of one sample share `sample_id` (unique per topic among samples in flight).
struct ChunkInfo {
    std::uint32_t sample_id = 0;
    std::uint32_t total_bytes = 0;
    std::uint32_t offset = 0;
};

/// One sample (or a piece of one) in a bundle.
struct BundleEntry {
    std::uint32_t topic_id = 0;  ///< the catalog's id of its topic
    std::uint16_t lane = 0;      ///< which of the topic's QoS offers (the catalog's lanes) it was published with
    EntryKind kind = EntryKind::data;
    std::int64_t source_ns = 0;  ///< the publisher's source timestamp, ns since the Unix epoch
    bool keyed = false;
    std::array<std::uint8_t, 16> key{};  ///< the instance (RTPS key hash) when keyed
    bool chunked = false;
    ChunkInfo chunk;  ///< when chunked
    /// The serialized sample as the publisher wrote it, encapsulation header included (for a chunk: its bytes).
    std::vector<std::uint8_t> payload;
};

struct Bundle {
    std::uint32_t sequence = 0;  ///< per gateway, from 0: a gap is bundles lost on the link
    std::vector<BundleEntry> entries;
    /// When the gateway wrote it, ns since the Unix epoch, kept to the microsecond: the relay's one-way delay. The
    /// gateway's transport leaves the DDS message's own timestamp (INFO_TS, 12 bytes) out of a bundle. Left out of
    /// the encoding when it lies further than MAX_STAMP_OFFSET_US from the base time (decodes as nullopt).
    std::optional<std::int64_t> write_ns;
};

enum class BundleCompression { none, zstd_if_smaller };

/// Why a byte string is not a bundle; the relay counts each.
enum class BundleError { none, truncated, bad_magic, bad_version, bad_checksum, malformed, too_large };
const char* to_string(BundleError error);

/// Bundle format, version 1. Integers are little-endian; a varint is LEB128, a signed one zigzag-coded first.
///   'T' 'B' version(1) flags(u8: bit 0 the entry section is zstd-compressed, bit 1 the write time follows)
///   varint sequence, i64 base_source_ns (the first entry's, 8 bytes),
///   [signed varint (write_ns - base_source_ns) in microseconds, at most 5 bytes], varint entry count
///   entry section: the entries, back to back; when compressed, varint raw length and the zstd frame
///   CRC-32 (zlib's) of everything before it, 4 bytes
/// Entry:
///   flags(u8: bits 0-1 kind, bit 2 keyed, bit 3 chunked, bit 4 plain CDR: the payload began with the
///         encapsulation header 00 01 00 00, which is left out and put back on decoding (the length counts what
///         is stored); bits 5-7 the lane, 7 meaning that a varint lane (7 to 65535) follows the topic id)
///   varint topic id, [varint lane], signed varint source_ns - base_source_ns (0 as base when there are no entries)
///   [16 key bytes]  [varint sample id, varint total bytes, varint offset]  varint payload length, payload
/// Everything is bounds-checked on decoding; no entry count, length or offset is trusted.
struct BundleCodec {
    static constexpr std::uint8_t VERSION = 1;
    /// No bundle decodes to more than this (a zstd bomb is refused).
    static constexpr std::size_t MAX_DECODED_BYTES = 1u << 20;

    /// Replaces `out` with the encoded bundle.
    static void encode(const Bundle& bundle, std::vector<std::uint8_t>& out,
                       BundleCompression compression = BundleCompression::none);
    /// Decodes `bytes` into `bundle`; on error `bundle` is unspecified.
    static BundleError decode(const std::uint8_t* bytes, std::size_t size, Bundle& bundle);

    /// The farthest the write time is from the base time and still encoded: its zigzag value fits 5 varint bytes.
    static constexpr std::int64_t MAX_STAMP_OFFSET_US = (std::int64_t{1} << 34) - 1;
    /// Bytes of a bundle beyond its entries, at most: header and checksum, uncompressed (the sequence and the
    /// entry count are charged as 5-byte varints, the write time at its 5 at most).
    static constexpr std::size_t MAX_FRAME_BYTES = 4 + 5 + 8 + 5 + 5 + 4;
    /// Exactly the bytes an entry takes in an uncompressed bundle whose base time is `source_ns - delta_ns`:
    /// what the scheduler charges before the bundle is built. `chunk`: null unless the entry is a chunk.
    static std::size_t entry_bytes(std::uint32_t topic_id, std::uint16_t lane, std::int64_t delta_ns,
                                   std::size_t payload_bytes, bool plain_cdr, bool keyed, const ChunkInfo* chunk);
    /// True if `payload` begins with the plain CDR encapsulation header (00 01 00 00), which the bundle leaves out.
    static bool plain_cdr(const std::uint8_t* payload, std::size_t size);
};

}  // namespace tgw::compact
