// The relay decodes compact WAN bundles off the link: any bytes give a bundle or a BundleError, never a read out of
// bounds; a bundle that decodes encodes again, plain or with zstd, to bytes that decode to the same bundle, and
// its size is the frame's plus what entry_bytes() charged for its entries.
// Each input is decoded twice: as it is, and with its last 4 bytes replaced by the right CRC-32, since nearly every
// mutation breaks the checksum and would otherwise never reach the parser behind it.
#include <zlib.h>

#include <algorithm>
#include <limits>
#include <string>

#include "compact/bundle_codec.hpp"
#include "test/fuzz/fuzz_target.hpp"
#include "test/unit/compact/bundle_entries.hpp"

namespace tgw::fuzz {

namespace {

using compact::Bundle;
using compact::BundleCodec;
using compact::BundleCompression;
using compact::BundleEntry;
using compact::BundleError;
using compact::EntryKind;

bool same(const BundleEntry& a, const BundleEntry& b) {
    return a.topic_id == b.topic_id && a.lane == b.lane && a.kind == b.kind && a.source_ns == b.source_ns &&
           a.keyed == b.keyed && a.key == b.key && a.chunked == b.chunked && a.chunk.sample_id == b.chunk.sample_id &&
           a.chunk.total_bytes == b.chunk.total_bytes && a.chunk.offset == b.chunk.offset && a.payload == b.payload;
}

bool same(const Bundle& a, const Bundle& b) {
    return a.sequence == b.sequence && a.write_ns == b.write_ns && a.entries.size() == b.entries.size() &&
           std::equal(a.entries.begin(), a.entries.end(), b.entries.begin(),
                      [](const BundleEntry& x, const BundleEntry& y) { return same(x, y); });
}

std::size_t varint_bytes(std::uint64_t value) {
    std::size_t n = 1;
    for (; value >= 0x80; value >>= 7)
        ++n;
    return n;
}

void check(const std::vector<std::uint8_t>& bytes) {
    Bundle bundle;
    const BundleError error = BundleCodec::decode(bytes.data(), bytes.size(), bundle);
    TGW_FUZZ_CHECK(error >= BundleError::none && error <= BundleError::too_large);
    if (error != BundleError::none)
        return;

    std::vector<std::uint8_t> plain;
    BundleCodec::encode(bundle, plain);
    Bundle again;
    TGW_FUZZ_CHECK(BundleCodec::decode(plain.data(), plain.size(), again) == BundleError::none);
    TGW_FUZZ_CHECK(same(again, bundle));
    std::vector<std::uint8_t> plain_again;
    BundleCodec::encode(again, plain_again);
    TGW_FUZZ_CHECK(plain_again == plain);

    std::size_t charged = 0;
    const std::int64_t base_ns = bundle.entries.empty() ? 0 : bundle.entries.front().source_ns;
    for (const BundleEntry& e : bundle.entries) {
        TGW_FUZZ_CHECK(e.kind == EntryKind::data || e.kind == EntryKind::dispose || e.kind == EntryKind::unregister);
        TGW_FUZZ_CHECK(!e.chunked || std::uint64_t{e.chunk.offset} + e.payload.size() <= e.chunk.total_bytes);
        const auto delta_ns =
            static_cast<std::int64_t>(static_cast<std::uint64_t>(e.source_ns) - static_cast<std::uint64_t>(base_ns));
        charged += BundleCodec::entry_bytes(e.topic_id, e.lane, delta_ns, e.payload.size(),
                                            BundleCodec::plain_cdr(e.payload.data(), e.payload.size()), e.keyed,
                                            e.chunked ? &e.chunk : nullptr);
    }
    std::size_t stamp_bytes = 0;
    if (bundle.write_ns) {
        const auto offset_us = static_cast<std::int64_t>(static_cast<std::uint64_t>(*bundle.write_ns) -
                                                         static_cast<std::uint64_t>(base_ns)) /
                               1000;
        stamp_bytes = varint_bytes(offset_us < 0 ? 2 * static_cast<std::uint64_t>(-offset_us) - 1
                                                 : 2 * static_cast<std::uint64_t>(offset_us));
        TGW_FUZZ_CHECK(stamp_bytes <= 5);
    }
    TGW_FUZZ_CHECK(plain.size() == 4 + varint_bytes(bundle.sequence) + 8 + stamp_bytes +
                                       varint_bytes(bundle.entries.size()) + charged + 4);
    TGW_FUZZ_CHECK(plain.size() <= BundleCodec::MAX_FRAME_BYTES + charged);

    std::vector<std::uint8_t> compressed;
    BundleCodec::encode(bundle, compressed, BundleCompression::zstd_if_smaller);
    TGW_FUZZ_CHECK(compressed.size() <= plain.size());
    TGW_FUZZ_CHECK(((compressed[3] & 0x01) == 0) == (compressed == plain));
    Bundle unpacked;
    TGW_FUZZ_CHECK(BundleCodec::decode(compressed.data(), compressed.size(), unpacked) == BundleError::none);
    TGW_FUZZ_CHECK(same(unpacked, bundle));
}

std::string as_string(const Bundle& bundle, BundleCompression compression) {
    std::vector<std::uint8_t> bytes;
    BundleCodec::encode(bundle, bytes, compression);
    return std::string(bytes.begin(), bytes.end());
}

using compact::test::entry;

}  // namespace

std::vector<std::string> seeds() {
    constexpr std::int64_t now_ns = 1'700'000'000'000'000'000;
    Bundle plain;
    plain.sequence = 3;
    plain.entries = {entry(1, now_ns, {0x00, 0x01, 0x00, 0x00, 0x2a, 0x00, 0x00, 0x00}),
                     entry(300, now_ns - 20'000'000'000, {0x00, 0x07, 0x00, 0x00, 0x01}),
                     entry(2, now_ns + 5, {}, EntryKind::unregister)};

    Bundle stamped = plain;
    stamped.write_ns = now_ns + 250'000'000;

    Bundle keyed;
    keyed.sequence = 70000;
    keyed.entries = {entry(4, now_ns, {0x00, 0x01, 0x00, 0x00, 0x05}), entry(4, now_ns + 1, {}, EntryKind::dispose)};
    for (BundleEntry& e : keyed.entries) {
        e.keyed = true;
        for (std::size_t i = 0; i < e.key.size(); ++i)
            e.key[i] = static_cast<std::uint8_t>(i * 17);
    }

    Bundle chunked;
    chunked.entries = {entry(9, now_ns, {0x00, 0x01, 0x00, 0x00, 1, 2, 3, 4}), entry(9, now_ns, {5, 6, 7, 8})};
    chunked.entries[0].chunked = true;
    chunked.entries[0].chunk = {12, 16, 0};
    chunked.entries[1].chunked = true;
    chunked.entries[1].chunk = {12, 16, 8};

    Bundle compressible;
    compressible.sequence = 9;
    std::vector<std::uint8_t> text = {0x00, 0x01, 0x00, 0x00};
    for (int i = 0; i < 30; ++i) {
        for (const char c : std::string("pose x=1.25 y=-3.5; "))
            text.push_back(static_cast<std::uint8_t>(c));
    }
    compressible.entries = {entry(5, now_ns, text), entry(5, now_ns + 100'000'000, text),
                            entry(6, std::numeric_limits<std::int64_t>::min(), {0x00, 0x00, 0x00, 0x00, 0x01})};

    return {
        as_string(plain, BundleCompression::none),    as_string(keyed, BundleCompression::none),
        as_string(chunked, BundleCompression::none),  as_string(compressible, BundleCompression::zstd_if_smaller),
        as_string(Bundle{}, BundleCompression::none), as_string(stamped, BundleCompression::none),
    };
}

}  // namespace tgw::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // Buffers of exactly the input's size, so that AddressSanitizer sees any read past it.
    std::vector<std::uint8_t> bytes(data, data + size);
    tgw::fuzz::check(bytes);
    if (bytes.size() >= 4) {
        const std::size_t body = bytes.size() - 4;
        const auto sum = static_cast<std::uint32_t>(crc32_z(0, bytes.data(), body));
        for (std::size_t i = 0; i < 4; ++i)
            bytes[body + i] = static_cast<std::uint8_t>(sum >> (8 * i));
        tgw::fuzz::check(bytes);
    }
    return 0;
}
