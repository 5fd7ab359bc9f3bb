#include "compact/bundle_codec.hpp"
#include "test/unit/compact/bundle_entries.hpp"

#include <gtest/gtest.h>
#include <zlib.h>
#include <zstd.h>

#include <cstring>
#include <limits>
#include <ostream>
#include <random>
#include <string>

namespace tgw::compact {

// Equality and printing for the tests; the codec itself needs neither. Here, not in the unnamed namespace, so that
// gtest finds them by argument-dependent lookup.
bool operator==(const ChunkInfo& a, const ChunkInfo& b) {
    return a.sample_id == b.sample_id && a.total_bytes == b.total_bytes && a.offset == b.offset;
}

bool operator==(const BundleEntry& a, const BundleEntry& b) {
    return a.topic_id == b.topic_id && a.lane == b.lane && a.kind == b.kind && a.source_ns == b.source_ns &&
           a.keyed == b.keyed && (!a.keyed || a.key == b.key) && a.chunked == b.chunked &&
           (!a.chunked || a.chunk == b.chunk) && a.payload == b.payload;
}

bool operator==(const Bundle& a, const Bundle& b) {
    return a.sequence == b.sequence && a.write_ns == b.write_ns && a.entries == b.entries;
}

void PrintTo(const BundleEntry& e, std::ostream* os) {
    *os << "{topic " << e.topic_id << ", kind " << static_cast<int>(e.kind) << ", source_ns " << e.source_ns
        << (e.keyed ? ", keyed" : "");
    if (e.chunked)
        *os << ", chunk " << e.chunk.sample_id << ' ' << e.chunk.offset << '/' << e.chunk.total_bytes;
    *os << ", " << e.payload.size() << " payload bytes}";
}

void PrintTo(const Bundle& b, std::ostream* os) {
    *os << "{sequence " << b.sequence << ", entries";
    for (const BundleEntry& e : b.entries) {
        *os << ' ';
        PrintTo(e, os);
    }
    *os << '}';
}

namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr std::int64_t SECOND_NS = 1'000'000'000;
constexpr std::int64_t NOW_NS = 1'700'000'000 * SECOND_NS;
constexpr std::int64_t INT64_MIN_NS = std::numeric_limits<std::int64_t>::min();
constexpr std::int64_t INT64_MAX_NS = std::numeric_limits<std::int64_t>::max();
constexpr std::uint32_t UINT32_MAX_ID = std::numeric_limits<std::uint32_t>::max();

/// A small valid entry, as bytes: data, topic 7, delta 0, payload AA BB.
const Bytes SMALL_ENTRY = {0x00, 0x07, 0x00, 0x02, 0xaa, 0xbb};

Bytes varint(std::uint64_t value) {
    Bytes out;
    do {
        out.push_back(static_cast<std::uint8_t>((value & 0x7f) | (value >= 0x80 ? 0x80 : 0)));
        value >>= 7;
    } while (value != 0);
    return out;
}

Bytes le(std::uint64_t value, std::size_t bytes) {
    Bytes out;
    for (std::size_t i = 0; i < bytes; ++i)
        out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
    return out;
}

Bytes cat(std::initializer_list<Bytes> parts) {
    Bytes out;
    for (const Bytes& part : parts)
        out.insert(out.end(), part.begin(), part.end());
    return out;
}

std::uint32_t crc(const Bytes& bytes, std::size_t size) {
    return static_cast<std::uint32_t>(crc32(0, bytes.data(), static_cast<uInt>(size)));
}

/// Replaces the last 4 bytes by the CRC-32 of the others, as an encoder would have written them.
void fix_checksum(Bytes& bundle) {
    const Bytes sum = le(crc(bundle, bundle.size() - 4), 4);
    std::copy(sum.begin(), sum.end(), bundle.end() - 4);
}

/// A bundle put together byte by byte, with a correct checksum.
Bytes bundle_bytes(std::uint8_t flags, std::uint64_t count, const Bytes& section, std::uint64_t sequence = 5,
                   std::int64_t base_ns = 0) {
    Bytes out = cat({{'T', 'B', 1, flags},
                     varint(sequence),
                     le(static_cast<std::uint64_t>(base_ns), 8),
                     varint(count),
                     section,
                     {0, 0, 0, 0}});
    fix_checksum(out);
    return out;
}

Bytes zstd_frame(const Bytes& raw) {
    Bytes frame(ZSTD_compressBound(raw.size()));
    frame.resize(ZSTD_compress(frame.data(), frame.size(), raw.data(), raw.size(), 3));
    return frame;
}

/// A frame whose header leaves its content size out, as a streaming compressor may.
Bytes zstd_frame_without_content_size(const Bytes& raw) {
    ZSTD_CCtx* context = ZSTD_createCCtx();
    ZSTD_CCtx_setParameter(context, ZSTD_c_contentSizeFlag, 0);
    Bytes frame(ZSTD_compressBound(raw.size()));
    frame.resize(ZSTD_compress2(context, frame.data(), frame.size(), raw.data(), raw.size()));
    ZSTD_freeCCtx(context);
    return frame;
}

std::int64_t wrapping_difference(std::int64_t a, std::int64_t b) {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) - static_cast<std::uint64_t>(b));
}

using compact::test::entry;

BundleEntry keyed(BundleEntry e, std::uint8_t first_key_byte) {
    e.keyed = true;
    for (std::size_t i = 0; i < e.key.size(); ++i)
        e.key[i] = static_cast<std::uint8_t>(first_key_byte + i);
    return e;
}

BundleEntry chunked(BundleEntry e, std::uint32_t sample_id, std::uint32_t total_bytes, std::uint32_t offset) {
    e.chunked = true;
    e.chunk = ChunkInfo{sample_id, total_bytes, offset};
    return e;
}

/// The bytes a scheduler charges for `e` in a bundle whose base time is `base_ns`.
std::size_t charge(const BundleEntry& e, std::int64_t base_ns) {
    return BundleCodec::entry_bytes(e.topic_id, e.lane, wrapping_difference(e.source_ns, base_ns), e.payload.size(),
                                    BundleCodec::plain_cdr(e.payload.data(), e.payload.size()), e.keyed,
                                    e.chunked ? &e.chunk : nullptr);
}

/// A number of 1 to `max_bits` bits, each width as likely as any other, so that every varint length comes up.
std::uint64_t random_width(std::mt19937_64& random, unsigned max_bits) {
    const unsigned bits = 1 + static_cast<unsigned>(random() % max_bits);
    return random() >> (64 - bits);
}

BundleEntry random_entry(std::mt19937_64& random, std::int64_t near_ns) {
    BundleEntry e;
    e.topic_id = static_cast<std::uint32_t>(random_width(random, 32));
    e.lane = static_cast<std::uint16_t>(random() % 2 == 0 ? random() % 8 : random_width(random, 16));
    e.kind = static_cast<EntryKind>(random() % 3);
    switch (random() % 3) {
        case 0:
            // Within an hour of `near_ns`, wrapping past the int64 extremes.
            e.source_ns = static_cast<std::int64_t>(static_cast<std::uint64_t>(near_ns) +
                                                    random() % (7200 * SECOND_NS) - 3600 * SECOND_NS);
            break;
        case 1:
            e.source_ns = static_cast<std::int64_t>(random());
            break;
        default:
            e.source_ns = near_ns;
            break;
    }
    e.payload.resize(random() % 300);
    for (std::uint8_t& b : e.payload)
        b = static_cast<std::uint8_t>(random());
    if (e.payload.size() >= 4 && random() % 2 == 0)
        std::memcpy(e.payload.data(), "\x00\x01\x00\x00", 4);
    if (random() % 2 == 0)
        e = keyed(std::move(e), static_cast<std::uint8_t>(random()));
    if (random() % 2 == 0) {
        const auto offset = static_cast<std::uint32_t>(random_width(random, 30));
        const auto total = static_cast<std::uint32_t>(offset + e.payload.size() + random() % 1000);
        e = chunked(std::move(e), static_cast<std::uint32_t>(random_width(random, 32)), total, offset);
    }
    return e;
}

class BundleCodecTest : public ::testing::Test {
  protected:
    static Bytes encoded(const Bundle& bundle, BundleCompression compression = BundleCompression::none) {
        Bytes out;
        BundleCodec::encode(bundle, out, compression);
        return out;
    }

    /// Decodes from a buffer of exactly `size` bytes, so that a sanitizer sees any read past them.
    static BundleError decode(const Bytes& bytes, std::size_t size) {
        const Bytes exact(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(size));
        Bundle bundle;
        return BundleCodec::decode(exact.data(), exact.size(), bundle);
    }
    static BundleError decode(const Bytes& bytes) { return decode(bytes, bytes.size()); }

    static Bundle round_trip(const Bundle& bundle, BundleCompression compression = BundleCompression::none) {
        const Bytes bytes = encoded(bundle, compression);
        Bundle decoded;
        decoded.sequence = 99;
        decoded.entries.push_back(entry(1, 2, {3}));
        EXPECT_EQ(BundleCodec::decode(bytes.data(), bytes.size(), decoded), BundleError::none);
        return decoded;
    }

    /// One of everything: kinds, keys, chunks, plain and other CDR, times both sides of the base.
    static Bundle varied_bundle() {
        Bundle b;
        b.sequence = 4242;
        b.entries = {
            entry(3, NOW_NS, {0x00, 0x01, 0x00, 0x00, 0x10, 0x20, 0x30}),
            keyed(entry(70000, NOW_NS - 20 * SECOND_NS, {0x00, 0x07, 0x00, 0x00, 1, 2}), 0x40),
            keyed(entry(70000, NOW_NS + 5, {}, EntryKind::dispose), 0x40),
            keyed(entry(9, NOW_NS + 3600 * SECOND_NS, {0x00, 0x01, 0x00, 0x00}, EntryKind::unregister), 0x80),
            chunked(entry(12, NOW_NS + 1, {0x00, 0x01, 0x00, 0x00, 9, 9, 9}), 77, 1000, 0),
            chunked(entry(12, NOW_NS + 1, Bytes(993, 0x5a)), 77, 1000, 7),
        };
        return b;
    }
};

TEST_F(BundleCodecTest, EncodesTheDocumentedLayoutByteForByte) {
    Bundle bundle;
    bundle.sequence = 300;
    bundle.entries = {
        entry(7, SECOND_NS, {0x00, 0x01, 0x00, 0x00, 0xaa, 0xbb}),
        keyed(entry(128, SECOND_NS - 1, {}, EntryKind::dispose), 0x00),
        chunked(entry(1, SECOND_NS + 64, {0x00, 0x07, 0x00, 0x00, 0x01}, EntryKind::unregister), 2, 300, 3),
    };

    const Bytes sut = encoded(bundle);

    const Bytes expected_body = cat({
        {'T', 'B', 1, 0x00},
        {0xac, 0x02},                                      // sequence 300
        {0x00, 0xca, 0x9a, 0x3b, 0x00, 0x00, 0x00, 0x00},  // base: the first entry's time
        {0x03},                                            // 3 entries
        {0x10, 0x07, 0x00, 0x02, 0xaa, 0xbb},              // plain CDR, topic 7, delta 0, header left out
        {0x05, 0x80, 0x01, 0x01},                          // dispose + keyed, topic 128, delta -1
        {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15},
        {0x00},                                // empty payload
        {0x0a, 0x01, 0x80, 0x01},              // unregister + chunked, topic 1, delta +64
        {0x02, 0xac, 0x02, 0x03},              // sample 2, total 300, offset 3
        {0x05, 0x00, 0x07, 0x00, 0x00, 0x01},  // XCDR2 kept whole
    });
    ASSERT_EQ(sut.size(), expected_body.size() + 4);
    EXPECT_EQ(Bytes(sut.begin(), sut.end() - 4), expected_body);
    EXPECT_EQ(Bytes(sut.end() - 4, sut.end()), le(crc(sut, sut.size() - 4), 4));
}

TEST_F(BundleCodecTest, EncodesTheWriteTimeAfterTheBaseTimeInMicroseconds) {
    Bundle bundle;
    bundle.sequence = 1;
    bundle.write_ns = SECOND_NS + 200'000'999;  // 200,000 us after the base; the last 999 ns are not kept
    bundle.entries = {entry(7, SECOND_NS, {0x00, 0x01, 0x00, 0x00, 0xaa})};

    const Bytes sut = encoded(bundle);

    const Bytes expected_body = cat({
        {'T', 'B', 1, 0x02},                               // the write time follows
        {0x01},                                            // sequence 1
        {0x00, 0xca, 0x9a, 0x3b, 0x00, 0x00, 0x00, 0x00},  // base: the first entry's time
        {0x80, 0xb5, 0x18},                                // zigzag(+200,000 us)
        {0x01},                                            // 1 entry
        {0x10, 0x07, 0x00, 0x01, 0xaa},
    });
    ASSERT_EQ(sut.size(), expected_body.size() + 4);
    EXPECT_EQ(Bytes(sut.begin(), sut.end() - 4), expected_body);
}

TEST_F(BundleCodecTest, RoundTripsTheWriteTimeToTheMicrosecondBothSidesOfTheBase) {
    for (const std::int64_t offset_us :
         {std::int64_t{0}, std::int64_t{1}, std::int64_t{-1}, std::int64_t{350'000}, std::int64_t{-20'000'000},
          BundleCodec::MAX_STAMP_OFFSET_US, -BundleCodec::MAX_STAMP_OFFSET_US}) {
        Bundle bundle;
        bundle.write_ns = NOW_NS + offset_us * 1000 + 123;
        bundle.entries = {entry(3, NOW_NS, {0x00, 0x01, 0x00, 0x00, 0x10})};

        const Bundle sut = round_trip(bundle, BundleCompression::zstd_if_smaller);

        ASSERT_TRUE(sut.write_ns.has_value()) << offset_us;
        EXPECT_EQ(*sut.write_ns, NOW_NS + offset_us * 1000) << offset_us;
        EXPECT_EQ(sut.entries, bundle.entries) << offset_us;
    }
}

TEST_F(BundleCodecTest, LeavesOutAWriteTimeTooFarFromTheBaseForFiveVarintBytes) {
    Bundle bundle;
    bundle.write_ns = NOW_NS + (BundleCodec::MAX_STAMP_OFFSET_US + 1) * 1000;
    bundle.entries = {entry(3, NOW_NS, {0x00, 0x01, 0x00, 0x00, 0x10})};
    Bundle unstamped = bundle;
    unstamped.write_ns.reset();

    const Bytes sut = encoded(bundle);

    EXPECT_EQ(sut, encoded(unstamped));
    EXPECT_FALSE(round_trip(bundle).write_ns.has_value());
}

TEST_F(BundleCodecTest, RejectsAWriteTimeFartherThanTheEncoderWritesOrMissingAsMalformed) {
    const auto stamped = [](std::uint64_t zigzag_offset) {
        Bytes out = cat(
            {{'T', 'B', 1, 0x02}, varint(5), le(0, 8), varint(zigzag_offset), varint(1), SMALL_ENTRY, {0, 0, 0, 0}});
        fix_checksum(out);
        return out;
    };
    const auto max_zigzag = 2 * static_cast<std::uint64_t>(BundleCodec::MAX_STAMP_OFFSET_US);

    EXPECT_EQ(decode(stamped(max_zigzag)), BundleError::none);
    EXPECT_EQ(decode(stamped(max_zigzag + 1)), BundleError::malformed);
    EXPECT_EQ(decode(stamped(std::numeric_limits<std::uint64_t>::max())), BundleError::malformed);
    // The flag without the offset: the entry count is read as the offset, and the entries do not parse.
    EXPECT_EQ(decode(bundle_bytes(0x02, 1, SMALL_ENTRY)), BundleError::malformed);
}

TEST_F(BundleCodecTest, RejectsAWriteTimeInABundleWithoutEntriesOrWhoseFirstEntryIsOffTheBase) {
    const auto stamped = [](std::uint64_t count, const Bytes& section) {
        Bytes out = cat({{'T', 'B', 1, 0x02}, varint(5), le(0, 8), varint(2), varint(count), section, {0, 0, 0, 0}});
        fix_checksum(out);
        return out;
    };
    Bytes off_base = SMALL_ENTRY;
    off_base[2] = 0x02;  // the time delta: +1 ns

    EXPECT_EQ(decode(stamped(1, SMALL_ENTRY)), BundleError::none);
    EXPECT_EQ(decode(stamped(0, {})), BundleError::malformed);
    EXPECT_EQ(decode(stamped(1, off_base)), BundleError::malformed);
}

TEST_F(BundleCodecTest, RoundTripsDataDisposeAndUnregisterEntries) {
    Bundle bundle;
    bundle.sequence = 1;
    bundle.entries = {entry(1, NOW_NS, {1, 2, 3}), entry(1, NOW_NS + 1, {4}, EntryKind::dispose),
                      entry(2, NOW_NS + 2, {}, EntryKind::unregister)};

    const Bundle sut = round_trip(bundle);

    EXPECT_EQ(sut, bundle);
}

TEST_F(BundleCodecTest, RoundTripsKeyedAndUnkeyedEntries) {
    Bundle bundle;
    bundle.entries = {keyed(entry(5, NOW_NS, {0x00, 0x01, 0x00, 0x00, 7}), 0xf0), entry(5, NOW_NS, {8}),
                      keyed(entry(6, NOW_NS, {}, EntryKind::dispose), 0x01)};

    const Bundle sut = round_trip(bundle);

    EXPECT_EQ(sut, bundle);
    ASSERT_EQ(sut.entries.size(), 3u);
    EXPECT_EQ(sut.entries[0].key[15], 0xff);
    EXPECT_FALSE(sut.entries[1].keyed);
}

TEST_F(BundleCodecTest, RoundTripsChunkedEntries) {
    Bundle bundle;
    bundle.entries = {
        chunked(entry(4, NOW_NS, {0x00, 0x01, 0x00, 0x00, 1, 2, 3, 4}), 1, 20, 0),
        chunked(entry(4, NOW_NS, Bytes(12, 0x33)), 1, 20, 8),
        chunked(entry(4, NOW_NS, {}), UINT32_MAX_ID, UINT32_MAX_ID, UINT32_MAX_ID),
        keyed(chunked(entry(5, NOW_NS, {9}), 2, 1, 0), 0x10),
    };

    const Bundle sut = round_trip(bundle);

    EXPECT_EQ(sut, bundle);
}

TEST_F(BundleCodecTest, RoundTripsTimesBothSidesOfTheBaseAndAtTheInt64Extremes) {
    for (const std::vector<std::int64_t>& times : std::vector<std::vector<std::int64_t>>{
             {NOW_NS, NOW_NS - 20 * SECOND_NS, NOW_NS + 3600 * SECOND_NS, INT64_MIN_NS, INT64_MAX_NS, 0, -1},
             {INT64_MIN_NS, INT64_MAX_NS, 0, INT64_MIN_NS + 1},
             {INT64_MAX_NS, INT64_MIN_NS, -1, NOW_NS},
             {-NOW_NS, NOW_NS}}) {
        Bundle bundle;
        for (const std::int64_t t : times)
            bundle.entries.push_back(entry(1, t, {0x42}));

        const Bundle sut = round_trip(bundle);

        EXPECT_EQ(sut, bundle);
    }
}

TEST_F(BundleCodecTest, RoundTripsTopicIdsAndSequencesUpToTheLargestUint32) {
    Bundle bundle;
    bundle.sequence = UINT32_MAX_ID;
    for (const std::uint32_t topic : {0u, 1u, 127u, 128u, 16383u, 16384u, 1u << 21, 1u << 28, UINT32_MAX_ID})
        bundle.entries.push_back(entry(topic, NOW_NS, {0x01}));

    const Bundle sut = round_trip(bundle);

    EXPECT_EQ(sut, bundle);
}

TEST_F(BundleCodecTest, RoundTripsEmptyPayloads) {
    Bundle bundle;
    bundle.entries = {entry(1, NOW_NS, {}), keyed(entry(2, NOW_NS, {}, EntryKind::dispose), 3),
                      chunked(entry(3, NOW_NS, {}), 4, 10, 10)};

    const Bundle sut = round_trip(bundle);

    EXPECT_EQ(sut, bundle);
}

TEST_F(BundleCodecTest, LeavesOutThePlainCdrHeaderAndPutsItBack) {
    Bundle with_header;
    with_header.entries = {entry(1, NOW_NS, {0x00, 0x01, 0x00, 0x00, 0xde, 0xad}), entry(1, NOW_NS, {0, 1, 0, 0})};
    Bundle without_header;
    without_header.entries = {entry(1, NOW_NS, {0xde, 0xad}), entry(1, NOW_NS, {})};

    const Bundle sut = round_trip(with_header);

    EXPECT_EQ(sut, with_header);
    EXPECT_EQ(encoded(with_header).size(), encoded(without_header).size());
    EXPECT_EQ(encoded(with_header)[14] & 0x10, 0x10);
}

TEST_F(BundleCodecTest, KeepsOtherEncapsulationHeadersWhole) {
    Bundle bundle;
    bundle.entries = {
        entry(1, NOW_NS, {0x00, 0x07, 0x00, 0x00, 0x11}),  // XCDR2 little-endian
        entry(1, NOW_NS, {0x00, 0x00, 0x00, 0x00, 0x22}),  // plain CDR big-endian
        entry(1, NOW_NS, {0x00, 0x03, 0x00, 0x00}),        // parameter list
        entry(1, NOW_NS, {0x00, 0x01, 0x00}),              // too short to be the header
        entry(1, NOW_NS, {0x00, 0x01, 0x00, 0x01, 0x33}),  // options set
    };

    const Bundle sut = round_trip(bundle);

    EXPECT_EQ(sut, bundle);
    std::size_t charged = 0;
    for (const BundleEntry& e : bundle.entries)
        charged += charge(e, NOW_NS);
    EXPECT_EQ(charged, 5 * 4 + 5 + 5 + 4 + 3 + 5);  // flags, topic, delta and length a byte each
}

TEST_F(BundleCodecTest, RoundTripsAnEmptyBundleWithAZeroBaseTime) {
    Bundle bundle;
    bundle.sequence = 17;

    const Bytes bytes = encoded(bundle);
    const Bundle sut = round_trip(bundle);

    EXPECT_EQ(sut, bundle);
    ASSERT_EQ(bytes.size(), 18u);
    EXPECT_EQ(Bytes(bytes.begin() + 5, bytes.begin() + 14), Bytes(9, 0x00));
}

TEST_F(BundleCodecTest, KnowsThePlainCdrHeader) {
    const std::uint8_t plain[] = {0x00, 0x01, 0x00, 0x00, 0x05};
    const std::uint8_t big_endian[] = {0x00, 0x00, 0x00, 0x00};
    const std::uint8_t xcdr2[] = {0x00, 0x07, 0x00, 0x00};

    EXPECT_TRUE(BundleCodec::plain_cdr(plain, 5));
    EXPECT_TRUE(BundleCodec::plain_cdr(plain, 4));
    EXPECT_FALSE(BundleCodec::plain_cdr(plain, 3));
    EXPECT_FALSE(BundleCodec::plain_cdr(nullptr, 0));
    EXPECT_FALSE(BundleCodec::plain_cdr(big_endian, 4));
    EXPECT_FALSE(BundleCodec::plain_cdr(xcdr2, 4));
}

TEST_F(BundleCodecTest, CompressesACompressibleEntrySectionIntoASmallerBundle) {
    Bundle bundle;
    bundle.sequence = 8;
    std::string text;
    for (int i = 0; i < 40; ++i)
        text += "battery/voltage=24.1 status=OK; ";
    std::vector<double> doubles(200);
    for (std::size_t i = 0; i < doubles.size(); ++i)
        doubles[i] = 0.25 * static_cast<double>(i % 8);
    Bytes numbers(doubles.size() * sizeof(double));
    std::memcpy(numbers.data(), doubles.data(), numbers.size());
    for (int i = 0; i < 10; ++i) {
        bundle.entries.push_back(
            entry(2, NOW_NS + i * SECOND_NS / 10, cat({{0x00, 0x01, 0x00, 0x00}, Bytes(text.begin(), text.end())})));
        bundle.entries.push_back(keyed(entry(3, NOW_NS + i * SECOND_NS / 10, numbers), 0x20));
    }

    const Bytes plain = encoded(bundle);
    const Bytes sut = encoded(bundle, BundleCompression::zstd_if_smaller);

    EXPECT_LT(sut.size(), plain.size() / 4);
    EXPECT_EQ(sut[3], 0x01);
    EXPECT_EQ(round_trip(bundle, BundleCompression::zstd_if_smaller), bundle);
}

TEST_F(BundleCodecTest, LeavesRandomBytesUncompressed) {
    std::mt19937_64 random(3);
    Bundle bundle;
    Bytes noise(2000);
    for (std::uint8_t& b : noise)
        b = static_cast<std::uint8_t>(random());
    bundle.entries = {entry(1, NOW_NS, noise)};

    const Bytes sut = encoded(bundle, BundleCompression::zstd_if_smaller);

    EXPECT_EQ(sut[3], 0x00);
    EXPECT_EQ(sut, encoded(bundle));
}

TEST_F(BundleCodecTest, SendsAnEntrySectionAboveMaxDecodedBytesUncompressed) {
    Bundle bundle;
    bundle.entries = {entry(1, NOW_NS, Bytes(BundleCodec::MAX_DECODED_BYTES + 100, 0x00))};

    const Bytes sut = encoded(bundle, BundleCompression::zstd_if_smaller);

    EXPECT_EQ(sut[3], 0x00);
    EXPECT_EQ(round_trip(bundle, BundleCompression::zstd_if_smaller), bundle);
}

TEST_F(BundleCodecTest, EntryBytesIsExactlyWhatEncodeWritesForAnEntry) {
    std::mt19937_64 random(11);
    for (int i = 0; i < 3000; ++i) {
        Bundle header_only;
        header_only.sequence = static_cast<std::uint32_t>(random_width(random, 32));
        Bundle one = header_only;
        one.entries = {random_entry(random, NOW_NS)};
        Bundle two = one;
        two.entries.push_back(random_entry(random, one.entries[0].source_ns));

        const std::int64_t base_ns = one.entries[0].source_ns;
        EXPECT_EQ(encoded(one).size() - encoded(header_only).size(), charge(one.entries[0], base_ns));
        EXPECT_EQ(encoded(two).size() - encoded(one).size(), charge(two.entries[1], base_ns));
    }
}

TEST_F(BundleCodecTest, FrameBytesAndEntryBytesAddUpToTheBundle) {
    std::mt19937_64 random(12);
    for (int i = 0; i < 300; ++i) {
        Bundle bundle;
        bundle.sequence = static_cast<std::uint32_t>(random_width(random, 32));
        const std::size_t count = 1 + random() % 127;
        std::size_t charged = 0;
        for (std::size_t n = 0; n < count; ++n) {
            bundle.entries.push_back(random_entry(random, NOW_NS));
            charged += charge(bundle.entries.back(), bundle.entries.front().source_ns);
        }

        const std::size_t sut = encoded(bundle).size();

        EXPECT_EQ(sut, 4 + varint(bundle.sequence).size() + 8 + 1 + charged + 4);
        EXPECT_LE(sut, BundleCodec::MAX_FRAME_BYTES + charged);
        EXPECT_LE(encoded(bundle, BundleCompression::zstd_if_smaller).size(), sut);
        EXPECT_EQ(round_trip(bundle), bundle);
    }
}

TEST_F(BundleCodecTest, RejectsEveryTruncationOfAValidBundle) {
    for (const BundleCompression compression : {BundleCompression::none, BundleCompression::zstd_if_smaller}) {
        Bundle bundle = varied_bundle();
        bundle.entries.push_back(entry(1, NOW_NS, Bytes(500, 0x61)));
        const Bytes bytes = encoded(bundle, compression);
        ASSERT_EQ(bytes[3], compression == BundleCompression::none ? 0x00 : 0x01);

        for (std::size_t size = 0; size < bytes.size(); ++size)
            EXPECT_NE(decode(bytes, size), BundleError::none) << size << " of " << bytes.size() << " bytes";
        EXPECT_EQ(decode(bytes), BundleError::none);
    }
    EXPECT_EQ(decode(encoded(Bundle{}), 17), BundleError::truncated);
}

TEST_F(BundleCodecTest, RejectsEverySingleBitFlip) {
    for (const BundleCompression compression : {BundleCompression::none, BundleCompression::zstd_if_smaller}) {
        Bundle bundle = varied_bundle();
        bundle.entries.push_back(entry(1, NOW_NS, Bytes(500, 0x61)));
        const Bytes bytes = encoded(bundle, compression);

        for (std::size_t bit = 0; bit < 8 * bytes.size(); ++bit) {
            Bytes flipped = bytes;
            flipped[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
            const BundleError expected = bit < 16   ? BundleError::bad_magic
                                         : bit < 24 ? BundleError::bad_version
                                                    : BundleError::bad_checksum;
            EXPECT_EQ(decode(flipped), expected) << "bit " << bit;
        }
    }
}

TEST_F(BundleCodecTest, DecodesABundlePutTogetherByHand) {
    const Bytes bytes = bundle_bytes(0x00, 1, SMALL_ENTRY, 5, NOW_NS);
    Bundle sut;

    ASSERT_EQ(BundleCodec::decode(bytes.data(), bytes.size(), sut), BundleError::none);

    Bundle expected;
    expected.sequence = 5;
    expected.entries = {entry(7, NOW_NS, {0xaa, 0xbb})};
    EXPECT_EQ(sut, expected);
}

TEST_F(BundleCodecTest, RejectsAnEntryCountLargerThanTheEntriesAsMalformed) {
    EXPECT_EQ(decode(bundle_bytes(0x00, 1000, SMALL_ENTRY)), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x00, 2, SMALL_ENTRY)), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x00, std::numeric_limits<std::uint64_t>::max(), SMALL_ENTRY)),
              BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, {})), BundleError::malformed);
}

TEST_F(BundleCodecTest, RejectsAPayloadLengthPastTheEndAsMalformed) {
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, {0x00, 0x07, 0x00, 0x03, 0xaa, 0xbb})), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, cat({{0x00, 0x07, 0x00}, varint(1ull << 40), {0xaa, 0xbb}}))),
              BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, {0x04, 0x07, 0x00, 1, 2, 3})), BundleError::malformed);  // key cut
}

TEST_F(BundleCodecTest, RejectsKindThreeAndUnknownBundleFlagsAsMalformed) {
    for (const std::uint8_t flags : {0x03, 0x1f, 0xe3}) {
        Bytes section = SMALL_ENTRY;
        section[0] = flags;
        EXPECT_EQ(decode(bundle_bytes(0x00, 1, section)), BundleError::malformed) << int{flags};
    }
    for (std::uint8_t flags = 0x04; flags != 0; flags = static_cast<std::uint8_t>(flags << 1))
        EXPECT_EQ(decode(bundle_bytes(flags, 1, SMALL_ENTRY)), BundleError::malformed) << int{flags};
}

TEST_F(BundleCodecTest, CarriesLanesUpToSixInTheFlagsAndLargerOnesAfterTheTopicId) {
    for (const std::uint16_t lane : {0, 1, 6, 7, 8, 127, 128, 65535}) {
        BundleEntry e = entry(3, NOW_NS, {0x00, 0x01, 0x00, 0x00, 0x42});
        e.lane = lane;
        Bundle sut{5, {e}, std::nullopt};
        Bytes bytes;
        BundleCodec::encode(sut, bytes);
        Bundle back;
        ASSERT_EQ(BundleCodec::decode(bytes.data(), bytes.size(), back), BundleError::none) << lane;
        EXPECT_EQ(back.entries.at(0).lane, lane);
        EXPECT_EQ(bytes.size(), 4 + 1 + 8 + 1 + charge(e, NOW_NS) + 4) << lane;
    }
}

TEST_F(BundleCodecTest, RejectsALaneAfterTheTopicIdThatWouldHaveFitTheFlagsOrSixteenBits) {
    // flags: lane field 7; topic 7, lane varint, delta 0, one payload byte
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, {0xe0, 0x07, 0x07, 0x00, 0x01, 0xaa})), BundleError::none);
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, {0xe0, 0x07, 0x06, 0x00, 0x01, 0xaa})), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, cat({{0xe0, 0x07}, varint(65536), {0x00, 0x01, 0xaa}}))),
              BundleError::malformed);
}

TEST_F(BundleCodecTest, RejectsBytesAfterTheLastEntryAsMalformed) {
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, cat({SMALL_ENTRY, {0x00}}))), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, cat({SMALL_ENTRY, SMALL_ENTRY}))), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x00, 2, cat({SMALL_ENTRY, SMALL_ENTRY}))), BundleError::none);
}

TEST_F(BundleCodecTest, RejectsAChunkReachingPastItsTotalAsMalformed) {
    // chunked, topic 7, delta 0, sample 1, total, offset, 3 payload bytes
    const auto chunk = [](std::uint8_t flags, std::uint8_t total, std::uint8_t offset) {
        return bundle_bytes(0x00, 1, {flags, 0x07, 0x00, 0x01, total, offset, 0x03, 0xaa, 0xbb, 0xcc});
    };

    EXPECT_EQ(decode(chunk(0x08, 10, 8)), BundleError::malformed);
    EXPECT_EQ(decode(chunk(0x08, 10, 7)), BundleError::none);
    EXPECT_EQ(decode(chunk(0x08, 2, 0)), BundleError::malformed);
    // A plain CDR chunk is 4 bytes longer than it travels.
    EXPECT_EQ(decode(chunk(0x18, 6, 0)), BundleError::malformed);
    EXPECT_EQ(decode(chunk(0x18, 7, 0)), BundleError::none);
    EXPECT_EQ(
        decode(bundle_bytes(
            0x00, 1, cat({{0x08, 0x07, 0x00, 0x01}, varint(UINT32_MAX_ID), varint(UINT32_MAX_ID), {0x01, 0xaa}}))),
        BundleError::malformed);
}

TEST_F(BundleCodecTest, RejectsVarintsTooWideOrLongerThanNeededAsMalformed) {
    const Bytes topic_2_32 = varint(1ull << 32);
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, cat({{0x00}, topic_2_32, {0x00, 0x00}}))), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, {0x00, 0x87, 0x00, 0x00, 0x00})), BundleError::malformed);  // over-long
    const Bytes delta_65_bits = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x02};
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, cat({{0x00, 0x07}, delta_65_bits, {0x00}}))), BundleError::malformed);
    const Bytes delta_11_bytes = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x81, 0x00};
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, cat({{0x00, 0x07}, delta_11_bytes, {0x00}}))), BundleError::malformed);
    const Bytes delta_64_bits = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x01};
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, cat({{0x00, 0x07}, delta_64_bits, {0x00}}))), BundleError::none);
    EXPECT_EQ(decode(bundle_bytes(0x00, 1, SMALL_ENTRY, 1ull << 32)), BundleError::malformed);  // sequence
}

TEST_F(BundleCodecTest, DecodesAZstdSectionPutTogetherByHand) {
    const Bytes section = cat({varint(SMALL_ENTRY.size()), zstd_frame(SMALL_ENTRY)});
    Bundle sut;
    const Bytes bytes = bundle_bytes(0x01, 1, section);

    ASSERT_EQ(BundleCodec::decode(bytes.data(), bytes.size(), sut), BundleError::none);

    ASSERT_EQ(sut.entries.size(), 1u);
    EXPECT_EQ(sut.entries[0].payload, (Bytes{0xaa, 0xbb}));
}

TEST_F(BundleCodecTest, RejectsARawLengthAboveMaxDecodedBytesAsTooLarge) {
    const Bytes bomb(2 * BundleCodec::MAX_DECODED_BYTES, 0x00);
    const Bytes frame = zstd_frame(bomb);
    ASSERT_LT(frame.size(), 1000u);

    EXPECT_EQ(decode(bundle_bytes(0x01, 1, cat({varint(bomb.size()), frame}))), BundleError::too_large);
    EXPECT_EQ(decode(bundle_bytes(0x01, 1, cat({varint(BundleCodec::MAX_DECODED_BYTES + 1), zstd_frame(SMALL_ENTRY)}))),
              BundleError::too_large);
    EXPECT_EQ(decode(bundle_bytes(0x01, 1, cat({varint(std::numeric_limits<std::uint64_t>::max()), frame}))),
              BundleError::too_large);
}

TEST_F(BundleCodecTest, RejectsAZstdFrameWhoseContentSizeDisagreesAsMalformed) {
    const Bytes frame = zstd_frame(SMALL_ENTRY);

    EXPECT_EQ(decode(bundle_bytes(0x01, 1, cat({varint(SMALL_ENTRY.size() - 1), frame}))), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x01, 1, cat({varint(SMALL_ENTRY.size() + 1), frame}))), BundleError::malformed);
    // A bomb announcing itself as small.
    const Bytes bomb = zstd_frame(Bytes(2 * BundleCodec::MAX_DECODED_BYTES, 0x00));
    EXPECT_EQ(decode(bundle_bytes(0x01, 1, cat({varint(100), bomb}))), BundleError::malformed);
    EXPECT_EQ(
        decode(bundle_bytes(0x01, 1, cat({varint(SMALL_ENTRY.size()), zstd_frame_without_content_size(SMALL_ENTRY)}))),
        BundleError::malformed);
}

TEST_F(BundleCodecTest, RejectsAZstdSectionThatIsNotExactlyOneFrameAsMalformed) {
    const Bytes frame = zstd_frame(SMALL_ENTRY);
    const Bytes raw_length = varint(SMALL_ENTRY.size());

    EXPECT_EQ(decode(bundle_bytes(0x01, 1, cat({raw_length, frame, {0x00}}))), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x01, 1, cat({raw_length, frame, zstd_frame({})}))), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x01, 1, cat({raw_length, Bytes(frame.begin(), frame.end() - 1)}))),
              BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x01, 1, cat({raw_length, {1, 2, 3, 4, 5, 6, 7, 8, 9}}))), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x01, 1, raw_length)), BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x01, 1, {})), BundleError::malformed);
    Bytes corrupt = frame;
    corrupt[corrupt.size() / 2 + 2] ^= 0xff;
    EXPECT_NE(decode(bundle_bytes(0x01, 1, cat({raw_length, corrupt}))), BundleError::none);
}

TEST_F(BundleCodecTest, RejectsCompressedEntriesThatDoNotParseAsMalformed) {
    const Bytes trailing = cat({SMALL_ENTRY, {0x00}});
    EXPECT_EQ(decode(bundle_bytes(0x01, 1, cat({varint(trailing.size()), zstd_frame(trailing)}))),
              BundleError::malformed);
    EXPECT_EQ(decode(bundle_bytes(0x01, 1000, cat({varint(SMALL_ENTRY.size()), zstd_frame(SMALL_ENTRY)}))),
              BundleError::malformed);
}

TEST_F(BundleCodecTest, RejectsAWrongChecksumBadMagicAndBadVersion) {
    Bytes bytes = bundle_bytes(0x00, 1, SMALL_ENTRY);
    Bytes wrong_sum = bytes;
    wrong_sum.back() ^= 0x01;
    Bytes magic = bytes;
    magic[0] = 'X';
    Bytes version = bytes;
    version[2] = 2;
    fix_checksum(magic);
    fix_checksum(version);
    Bytes version_zero = version;
    version_zero[2] = 0;
    fix_checksum(version_zero);

    EXPECT_EQ(decode(wrong_sum), BundleError::bad_checksum);
    EXPECT_EQ(decode(magic), BundleError::bad_magic);
    EXPECT_EQ(decode(version), BundleError::bad_version);
    EXPECT_EQ(decode(version_zero), BundleError::bad_version);
    EXPECT_EQ(decode(Bytes{'T', 'X'}), BundleError::bad_magic);
    EXPECT_EQ(decode(Bytes{'T', 'B', 9}), BundleError::bad_version);
}

TEST_F(BundleCodecTest, RejectsInputShorterThanTheSmallestBundleAsTruncated) {
    EXPECT_EQ(decode(Bytes{}), BundleError::truncated);
    EXPECT_EQ(decode(Bytes{'T'}), BundleError::truncated);
    EXPECT_EQ(decode(Bytes{'T', 'B'}), BundleError::truncated);
    EXPECT_EQ(decode(Bytes{'T', 'B', 1, 0, 0}), BundleError::truncated);
    Bundle sut;
    EXPECT_EQ(BundleCodec::decode(nullptr, 0, sut), BundleError::truncated);
}

TEST_F(BundleCodecTest, NamesEveryErrorInAFewLowercaseWords) {
    EXPECT_STREQ(to_string(BundleError::none), "none");
    EXPECT_STREQ(to_string(BundleError::truncated), "truncated");
    EXPECT_STREQ(to_string(BundleError::bad_magic), "bad magic");
    EXPECT_STREQ(to_string(BundleError::bad_version), "bad version");
    EXPECT_STREQ(to_string(BundleError::bad_checksum), "bad checksum");
    EXPECT_STREQ(to_string(BundleError::malformed), "malformed");
    EXPECT_STREQ(to_string(BundleError::too_large), "too large");
}

}  // namespace
}  // namespace tgw::compact
