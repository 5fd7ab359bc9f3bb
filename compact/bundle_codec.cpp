#include "compact/bundle_codec.hpp"

#include <zlib.h>

#include <cstring>
#include <limits>

#include "base/byte_order.hpp"
#include "compact/zstd_frame.hpp"

namespace tgw::compact {

namespace {

constexpr std::uint8_t MAGIC[2] = {'T', 'B'};
constexpr std::uint8_t BUNDLE_COMPRESSED = 0x01;
constexpr std::uint8_t BUNDLE_STAMPED = 0x02;
constexpr std::int64_t NS_PER_US = 1000;

constexpr std::uint8_t ENTRY_KIND_MASK = 0x03;
constexpr std::uint8_t ENTRY_KEYED = 0x04;
constexpr std::uint8_t ENTRY_CHUNKED = 0x08;
constexpr std::uint8_t ENTRY_PLAIN_CDR = 0x10;
constexpr unsigned ENTRY_LANE_SHIFT = 5;
constexpr std::uint8_t ENTRY_LANE_MASK = 0xe0;
/// A lane field of 7: the lane (7 or more) follows the topic id as a varint.
constexpr std::uint8_t LANE_IN_VARINT = 7;

constexpr std::uint8_t PLAIN_CDR_HEADER[4] = {0x00, 0x01, 0x00, 0x00};
constexpr std::size_t PLAIN_CDR_HEADER_BYTES = sizeof PLAIN_CDR_HEADER;
constexpr std::size_t KEY_BYTES = 16;
constexpr std::size_t HEADER_BYTES = 4;  // magic, version, flags
constexpr std::size_t BASE_TIME_BYTES = sizeof(std::uint64_t);
constexpr std::size_t CHECKSUM_BYTES = sizeof(std::uint32_t);
/// Header, a one-byte sequence, base time, a one-byte entry count and the checksum: no bundle is shorter.
constexpr std::size_t MIN_BUNDLE_BYTES = HEADER_BYTES + 1 + BASE_TIME_BYTES + 1 + CHECKSUM_BYTES;
/// Flags, topic id, time delta and payload length, a byte each: no entry is shorter.
constexpr std::size_t MIN_ENTRY_BYTES = 4;

// Zigzag in unsigned arithmetic: shifting a negative value is what it must not do.
std::uint64_t zigzag(std::int64_t value) {
    const auto bits = static_cast<std::uint64_t>(value);
    return (bits << 1) ^ (std::uint64_t{0} - (bits >> 63));
}

std::int64_t unzigzag(std::uint64_t value) {
    return static_cast<std::int64_t>((value >> 1) ^ (std::uint64_t{0} - (value & 1)));
}

// Differences of timestamps wrap (mod 2^64) rather than overflow, so that any two int64 times round-trip.
std::int64_t wrapping_difference(std::int64_t a, std::int64_t b) {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) - static_cast<std::uint64_t>(b));
}

std::int64_t wrapping_sum(std::int64_t a, std::int64_t b) {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) + static_cast<std::uint64_t>(b));
}

std::size_t varint_bytes(std::uint64_t value) {
    std::size_t n = 1;
    while (value >= 0x80) {
        value >>= 7;
        ++n;
    }
    return n;
}

void put_varint(std::vector<std::uint8_t>& out, std::uint64_t value) {
    while (value >= 0x80) {
        out.push_back(static_cast<std::uint8_t>(value | 0x80));
        value >>= 7;
    }
    out.push_back(static_cast<std::uint8_t>(value));
}

void put_le(std::vector<std::uint8_t>& out, std::uint64_t value, std::size_t bytes) {
    for (std::size_t i = 0; i < bytes; ++i)
        out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

std::uint32_t checksum(const std::uint8_t* bytes, std::size_t size) {
    return static_cast<std::uint32_t>(crc32_z(crc32_z(0, Z_NULL, 0), bytes, size));
}

/// Reads forward through a byte range; each read returns false, and reads nothing, if the range ends first.
class Reader {
  public:
    Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

    std::size_t remaining() const { return size_ - at_; }
    const std::uint8_t* position() const { return data_ + at_; }

    bool byte(std::uint8_t& value) {
        if (at_ == size_)
            return false;
        value = data_[at_++];
        return true;
    }

    bool bytes(std::size_t n, const std::uint8_t*& begin) {
        if (n > remaining())
            return false;
        begin = data_ + at_;
        at_ += n;
        return true;
    }

    /// A LEB128 varint of at most 64 bits, in its shortest form (an over-long one is as good as malformed: the
    /// encoder never writes one, and accepting it would give one bundle many encodings).
    bool varint(std::uint64_t& value) {
        value = 0;
        for (unsigned shift = 0; shift < 64; shift += 7) {
            std::uint8_t b = 0;
            if (!byte(b))
                return false;
            if (shift == 63 && b > 1)  // bits beyond the 64th
                return false;
            value |= std::uint64_t{b & 0x7fu} << shift;
            if ((b & 0x80) == 0)
                return b != 0 || shift == 0;
        }
        return false;
    }

    bool varint32(std::uint32_t& value) {
        std::uint64_t wide = 0;
        if (!varint(wide) || wide > std::numeric_limits<std::uint32_t>::max())
            return false;
        value = static_cast<std::uint32_t>(wide);
        return true;
    }

  private:
    const std::uint8_t* data_;
    std::size_t size_;
    std::size_t at_ = 0;
};

void put_entry(std::vector<std::uint8_t>& out, const BundleEntry& entry, std::int64_t base_ns) {
    const bool plain = BundleCodec::plain_cdr(entry.payload.data(), entry.payload.size());
    std::uint8_t flags = static_cast<std::uint8_t>(entry.kind) & ENTRY_KIND_MASK;
    if (entry.keyed)
        flags |= ENTRY_KEYED;
    if (entry.chunked)
        flags |= ENTRY_CHUNKED;
    if (plain)
        flags |= ENTRY_PLAIN_CDR;
    const bool wide_lane = entry.lane >= LANE_IN_VARINT;
    flags |= static_cast<std::uint8_t>((wide_lane ? LANE_IN_VARINT : entry.lane) << ENTRY_LANE_SHIFT);
    out.push_back(flags);
    put_varint(out, entry.topic_id);
    if (wide_lane)
        put_varint(out, entry.lane);
    put_varint(out, zigzag(wrapping_difference(entry.source_ns, base_ns)));
    if (entry.keyed)
        out.insert(out.end(), entry.key.begin(), entry.key.end());
    if (entry.chunked) {
        put_varint(out, entry.chunk.sample_id);
        put_varint(out, entry.chunk.total_bytes);
        put_varint(out, entry.chunk.offset);
    }
    const std::size_t skip = plain ? PLAIN_CDR_HEADER_BYTES : 0;
    put_varint(out, entry.payload.size() - skip);
    out.insert(out.end(), entry.payload.begin() + static_cast<std::ptrdiff_t>(skip), entry.payload.end());
}

bool get_entry(Reader& in, std::int64_t base_ns, BundleEntry& entry) {
    std::uint8_t flags = 0;
    if (!in.byte(flags) || (flags & ENTRY_KIND_MASK) == 3)
        return false;
    entry.kind = static_cast<EntryKind>(flags & ENTRY_KIND_MASK);
    entry.keyed = (flags & ENTRY_KEYED) != 0;
    entry.chunked = (flags & ENTRY_CHUNKED) != 0;
    const auto lane_field = static_cast<std::uint8_t>((flags & ENTRY_LANE_MASK) >> ENTRY_LANE_SHIFT);
    std::uint64_t delta = 0;
    if (!in.varint32(entry.topic_id))
        return false;
    entry.lane = lane_field;
    if (lane_field == LANE_IN_VARINT) {
        std::uint32_t lane = 0;
        // Only a lane that does not fit the field may follow, and it must fit 16 bits.
        if (!in.varint32(lane) || lane < LANE_IN_VARINT || lane > std::numeric_limits<std::uint16_t>::max())
            return false;
        entry.lane = static_cast<std::uint16_t>(lane);
    }
    if (!in.varint(delta))
        return false;
    entry.source_ns = wrapping_sum(base_ns, unzigzag(delta));
    if (entry.keyed) {
        const std::uint8_t* key = nullptr;
        if (!in.bytes(KEY_BYTES, key))
            return false;
        std::memcpy(entry.key.data(), key, KEY_BYTES);
    }
    if (entry.chunked && !(in.varint32(entry.chunk.sample_id) && in.varint32(entry.chunk.total_bytes) &&
                           in.varint32(entry.chunk.offset)))
        return false;
    std::uint64_t length = 0;
    const std::uint8_t* payload = nullptr;
    if (!in.varint(length) || length > in.remaining() || !in.bytes(static_cast<std::size_t>(length), payload))
        return false;
    entry.payload.clear();
    if ((flags & ENTRY_PLAIN_CDR) != 0) {
        entry.payload.reserve(PLAIN_CDR_HEADER_BYTES + length);
        entry.payload.assign(std::begin(PLAIN_CDR_HEADER), std::end(PLAIN_CDR_HEADER));
    }
    entry.payload.insert(entry.payload.end(), payload, payload + length);
    return !entry.chunked ||
           std::uint64_t{entry.chunk.offset} + entry.payload.size() <= std::uint64_t{entry.chunk.total_bytes};
}

/// The compressed form of an entry section (varint raw length, one zstd frame), or nothing if not smaller.
bool compress_section(const std::uint8_t* raw, std::size_t raw_size, std::vector<std::uint8_t>& out) {
    // The decoder refuses more than MAX_DECODED_BYTES; such a section travels as it is.
    if (raw_size == 0 || raw_size > BundleCodec::MAX_DECODED_BYTES)
        return false;
    out.clear();
    put_varint(out, raw_size);
    return zstd_frame(raw, raw_size, out) && out.size() < raw_size;
}

/// Decompresses the section `bytes` (varint raw length, one zstd frame) into `raw`.
BundleError decompress_section(const std::uint8_t* bytes, std::size_t size, std::vector<std::uint8_t>& raw) {
    Reader in(bytes, size);
    std::uint64_t raw_size = 0;
    if (!in.varint(raw_size))
        return BundleError::malformed;
    if (raw_size > BundleCodec::MAX_DECODED_BYTES)
        return BundleError::too_large;
    // A frame of more than the section said, or of less, is as malformed as one that does not decode.
    const bool whole =
        unzstd_frame(in.position(), in.remaining(), static_cast<std::size_t>(raw_size), raw) == FrameError::none &&
        raw.size() == raw_size;
    return whole ? BundleError::none : BundleError::malformed;
}

}  // namespace

const char* to_string(BundleError error) {
    switch (error) {
        case BundleError::none:
            return "none";
        case BundleError::truncated:
            return "truncated";
        case BundleError::bad_magic:
            return "bad magic";
        case BundleError::bad_version:
            return "bad version";
        case BundleError::bad_checksum:
            return "bad checksum";
        case BundleError::malformed:
            return "malformed";
        case BundleError::too_large:
            return "too large";
    }
    return "unknown";
}

bool BundleCodec::plain_cdr(const std::uint8_t* payload, std::size_t size) {
    return size >= PLAIN_CDR_HEADER_BYTES && std::memcmp(payload, PLAIN_CDR_HEADER, PLAIN_CDR_HEADER_BYTES) == 0;
}

std::size_t BundleCodec::entry_bytes(std::uint32_t topic_id, std::uint16_t lane, std::int64_t delta_ns,
                                     std::size_t payload_bytes, bool plain_cdr, bool keyed, const ChunkInfo* chunk) {
    const std::size_t stored =
        plain_cdr && payload_bytes >= PLAIN_CDR_HEADER_BYTES ? payload_bytes - PLAIN_CDR_HEADER_BYTES : payload_bytes;
    std::size_t n = 1 + varint_bytes(topic_id) + varint_bytes(zigzag(delta_ns)) + varint_bytes(stored) + stored;
    if (lane >= LANE_IN_VARINT)
        n += varint_bytes(lane);
    if (keyed)
        n += KEY_BYTES;
    if (chunk != nullptr)
        n += varint_bytes(chunk->sample_id) + varint_bytes(chunk->total_bytes) + varint_bytes(chunk->offset);
    return n;
}

void BundleCodec::encode(const Bundle& bundle, std::vector<std::uint8_t>& out, BundleCompression compression) {
    out.clear();
    const std::int64_t base_ns = bundle.entries.empty() ? 0 : bundle.entries.front().source_ns;
    std::size_t entries_size = 0;
    for (const BundleEntry& e : bundle.entries) {
        entries_size +=
            entry_bytes(e.topic_id, e.lane, wrapping_difference(e.source_ns, base_ns), e.payload.size(),
                        plain_cdr(e.payload.data(), e.payload.size()), e.keyed, e.chunked ? &e.chunk : nullptr);
    }
    out.reserve(MAX_FRAME_BYTES + entries_size);

    out.insert(out.end(), std::begin(MAGIC), std::end(MAGIC));
    out.push_back(VERSION);
    out.push_back(0);  // flags, set below
    put_varint(out, bundle.sequence);
    put_le(out, static_cast<std::uint64_t>(base_ns), BASE_TIME_BYTES);
    if (bundle.write_ns) {
        // Rounded down, so that a decoded time encodes again to the same offset.
        const std::int64_t offset_ns = wrapping_difference(*bundle.write_ns, base_ns);
        const std::int64_t offset_us = offset_ns / NS_PER_US - (offset_ns % NS_PER_US < 0 ? 1 : 0);
        if (offset_us >= -BundleCodec::MAX_STAMP_OFFSET_US && offset_us <= BundleCodec::MAX_STAMP_OFFSET_US) {
            put_varint(out, zigzag(offset_us));
            out[3] |= BUNDLE_STAMPED;
        }
    }
    put_varint(out, bundle.entries.size());
    const std::size_t section = out.size();
    for (const BundleEntry& e : bundle.entries)
        put_entry(out, e, base_ns);

    if (compression == BundleCompression::zstd_if_smaller) {
        std::vector<std::uint8_t> compressed;
        if (compress_section(out.data() + section, out.size() - section, compressed)) {
            out.resize(section);
            out.insert(out.end(), compressed.begin(), compressed.end());
            out[3] |= BUNDLE_COMPRESSED;
        }
    }
    put_le(out, checksum(out.data(), out.size()), CHECKSUM_BYTES);
}

BundleError BundleCodec::decode(const std::uint8_t* bytes, std::size_t size, Bundle& bundle) {
    bundle.sequence = 0;
    bundle.write_ns.reset();
    bundle.entries.clear();
    if (size < sizeof MAGIC)
        return BundleError::truncated;
    if (std::memcmp(bytes, MAGIC, sizeof MAGIC) != 0)
        return BundleError::bad_magic;
    if (size < sizeof MAGIC + 1)
        return BundleError::truncated;
    if (bytes[2] != VERSION)
        return BundleError::bad_version;
    if (size < MIN_BUNDLE_BYTES)
        return BundleError::truncated;
    const std::size_t body = size - CHECKSUM_BYTES;
    if (checksum(bytes, body) != base::load_little_endian<std::uint32_t>(bytes + body))
        return BundleError::bad_checksum;

    const std::uint8_t flags = bytes[3];
    if ((flags & ~(BUNDLE_COMPRESSED | BUNDLE_STAMPED)) != 0)
        return BundleError::malformed;
    Reader header(bytes + HEADER_BYTES, body - HEADER_BYTES);
    const std::uint8_t* base_time = nullptr;
    if (!header.varint32(bundle.sequence) || !header.bytes(BASE_TIME_BYTES, base_time))
        return BundleError::malformed;
    const auto base_ns = static_cast<std::int64_t>(base::load_little_endian<std::uint64_t>(base_time));
    if ((flags & BUNDLE_STAMPED) != 0) {
        std::uint64_t offset = 0;
        // Only what the encoder writes: an offset in range (which also keeps the product below from overflowing).
        if (!header.varint(offset) || offset > zigzag(BundleCodec::MAX_STAMP_OFFSET_US))
            return BundleError::malformed;
        bundle.write_ns = wrapping_sum(base_ns, unzigzag(offset) * NS_PER_US);
    }
    std::uint64_t count = 0;
    if (!header.varint(count))
        return BundleError::malformed;

    const std::uint8_t* section = header.position();
    std::size_t section_size = header.remaining();
    std::vector<std::uint8_t> raw;
    if ((flags & BUNDLE_COMPRESSED) != 0) {
        const BundleError error = decompress_section(section, section_size, raw);
        if (error != BundleError::none)
            return error;
        section = raw.data();
        section_size = raw.size();
    }
    // The count is only believed as far as the bytes there are could hold that many entries.
    if (count > section_size / MIN_ENTRY_BYTES)
        return BundleError::malformed;
    Reader in(section, section_size);
    bundle.entries.resize(static_cast<std::size_t>(count));
    for (BundleEntry& entry : bundle.entries) {
        if (!get_entry(in, base_ns, entry))
            return BundleError::malformed;
    }
    if (in.remaining() != 0)
        return BundleError::malformed;
    // The write time counts from the first entry's time, as the encoder writes it: with no entry, or a first entry
    // off the base, it would encode again to other bytes.
    if (bundle.write_ns && (bundle.entries.empty() || bundle.entries.front().source_ns != base_ns))
        return BundleError::malformed;
    return BundleError::none;
}

}  // namespace tgw::compact
