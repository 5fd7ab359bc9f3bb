#include "gateway/dds/gap_for_repair.hpp"

#include <algorithm>
#include <array>
#include <cstring>

#include "wire/rtps_submessage.hpp"

namespace tgw::dds {

using namespace wire::rtps_bytes;

namespace {

/// readerId, writerId, gapStart, gapList's bitmapBase and numBits (0: no bitmap).
constexpr std::uint16_t GAP_BODY_BYTES = 4 + 4 + 8 + 8 + 4;
constexpr std::size_t SAMPLE_READER_ID_OFFSET = 4;

struct Gapped {
    std::array<std::uint8_t, 4> reader{};
    std::array<std::uint8_t, 4> writer{};
    std::uint64_t sequence = 0;
    bool operator==(const Gapped& other) const {
        return reader == other.reader && writer == other.writer && sequence == other.sequence;
    }
};

void put_u32_le(std::vector<std::uint8_t>& out, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) {
        out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
    }
}

void put_sequence_le(std::vector<std::uint8_t>& out, std::uint64_t sequence) {
    put_u32_le(out, static_cast<std::uint32_t>(sequence >> 32));
    put_u32_le(out, static_cast<std::uint32_t>(sequence));
}

}  // namespace

bool gap_for_repair(const std::uint8_t* message, std::size_t size, std::vector<std::uint8_t>& out) {
    if (size < MESSAGE_HEADER_BYTES || std::memcmp(message, "RTPS", 4) != 0) {
        return false;
    }
    constexpr std::size_t MAX_GAPPED = 32;  // a repair message holds a few samples
    std::array<Gapped, MAX_GAPPED> gapped;
    std::size_t n = 0;
    const std::uint8_t* destination = nullptr;  // the INFO_DST, kept: the GAP is for the same participant
    std::size_t destination_bytes = 0;
    std::size_t pos = MESSAGE_HEADER_BYTES;
    while (pos + SUBMESSAGE_HEADER_BYTES <= size) {
        const std::uint8_t* sub = message + pos;
        const std::size_t length = octets_to_next_header(sub);
        if (sub[0] == SRTPS_PREFIX || pos + SUBMESSAGE_HEADER_BYTES + length > size) {
            return false;
        }
        const std::uint8_t* body = sub + SUBMESSAGE_HEADER_BYTES;
        const bool le = (sub[1] & FLAG_LITTLE_ENDIAN) != 0;
        if (sub[0] == INFO_DST && destination == nullptr) {
            destination = sub;
            destination_bytes = SUBMESSAGE_HEADER_BYTES + length;
        } else if ((sub[0] == DATA && length >= DATA_FIELDS_BYTES) ||
                   (sub[0] == DATA_FRAG && length >= DATA_FRAG_FIELDS_BYTES)) {
            Gapped g;
            std::memcpy(g.reader.data(), body + SAMPLE_READER_ID_OFFSET, g.reader.size());
            std::memcpy(g.writer.data(), body + SAMPLE_WRITER_ID_OFFSET, g.writer.size());
            g.sequence = static_cast<std::uint64_t>(read_u32(body + SAMPLE_SEQUENCE_OFFSET, le)) << 32 |
                         read_u32(body + SAMPLE_SEQUENCE_OFFSET + 4, le);
            if (std::find(gapped.begin(), gapped.begin() + static_cast<std::ptrdiff_t>(n), g) ==
                    gapped.begin() + static_cast<std::ptrdiff_t>(n) &&
                n < MAX_GAPPED) {
                gapped[n++] = g;
            }
        }
        if (length == 0) {
            break;  // runs to the end of the message
        }
        pos += SUBMESSAGE_HEADER_BYTES + ((length + 3) & ~std::size_t{3});
    }
    if (n == 0) {
        return false;
    }
    out.assign(message, message + MESSAGE_HEADER_BYTES);
    if (destination != nullptr) {
        out.insert(out.end(), destination, destination + destination_bytes);
    }
    for (std::size_t i = 0; i < n; ++i) {
        out.push_back(GAP);
        out.push_back(FLAG_LITTLE_ENDIAN);
        out.push_back(static_cast<std::uint8_t>(GAP_BODY_BYTES & 0xff));
        out.push_back(static_cast<std::uint8_t>(GAP_BODY_BYTES >> 8));
        out.insert(out.end(), gapped[i].reader.begin(), gapped[i].reader.end());
        out.insert(out.end(), gapped[i].writer.begin(), gapped[i].writer.end());
        put_sequence_le(out, gapped[i].sequence);      // gapStart: this sample
        put_sequence_le(out, gapped[i].sequence + 1);  // gapList: none beyond it
        put_u32_le(out, 0);
    }
    return true;
}

}  // namespace tgw::dds
