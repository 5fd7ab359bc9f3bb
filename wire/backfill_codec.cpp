#include "wire/backfill_codec.hpp"

#include <algorithm>
#include <cstdio>
#include <exception>

#include <fastdds/rtps/common/SerializedPayload.h>

#include "base/hex.hpp"

namespace tgw::wire {

namespace {

using eprosima::fastrtps::rtps::SerializedPayload_t;

/// CDR's encapsulation identifiers of plain CDR, big and little endian (the first two bytes of a payload).
constexpr std::uint8_t PLAIN_CDR_BIG_ENDIAN = 0x00;
constexpr std::uint8_t PLAIN_CDR_LITTLE_ENDIAN = 0x01;
constexpr std::size_t ENCAPSULATION_BYTES = 4;

}  // namespace

std::optional<std::array<std::uint8_t, 16>> log_id_octets(const std::string& hex) {
    std::array<std::uint8_t, 16> octets{};
    if (hex.size() != 2 * octets.size())
        return std::nullopt;
    for (std::size_t i = 0; i < octets.size(); ++i) {
        const int high = base::hex_digit(hex[2 * i]);
        const int low = base::hex_digit(hex[2 * i + 1]);
        if (high < 0 || low < 0)
            return std::nullopt;
        octets[i] = static_cast<std::uint8_t>(high * 16 + low);
    }
    return octets;
}

std::string log_id_hex(const std::array<std::uint8_t, 16>& octets) {
    std::string hex;
    hex.reserve(2 * octets.size());
    for (const std::uint8_t octet : octets) {
        char pair[3];
        std::snprintf(pair, sizeof pair, "%02x", octet);
        hex += pair;
    }
    return hex;
}

std::vector<std::uint8_t> encode_backfill(const idl::BackfillSample& sample) {
    idl::BackfillSamplePubSubType type;
    // Fast DDS's type support takes a void*, and only reads it to serialize.
    auto* data = const_cast<idl::BackfillSample*>(&sample);
    SerializedPayload_t payload(type.getSerializedSizeProvider(data)());
    if (!type.serialize(data, &payload))
        return {};
    return std::vector<std::uint8_t>(payload.data, payload.data + payload.length);
}

std::optional<std::int64_t> backfill_row_id(const std::vector<std::uint8_t>& payload) {
    if (payload.size() < ENCAPSULATION_BYTES + 8 || payload[0] != 0x00 ||
        (payload[1] != PLAIN_CDR_BIG_ENDIAN && payload[1] != PLAIN_CDR_LITTLE_ENDIAN))
        return std::nullopt;
    std::uint64_t row = 0;
    for (std::size_t i = 0; i < 8; ++i) {
        const std::size_t at =
            payload[1] == PLAIN_CDR_LITTLE_ENDIAN ? ENCAPSULATION_BYTES + 7 - i : ENCAPSULATION_BYTES + i;
        row = (row << 8) | payload[at];
    }
    return static_cast<std::int64_t>(row);
}

std::optional<idl::BackfillSample> decode_backfill(const std::vector<std::uint8_t>& payload) {
    SerializedPayload_t serialized(static_cast<std::uint32_t>(payload.size()));
    std::copy(payload.begin(), payload.end(), serialized.data);
    serialized.length = static_cast<std::uint32_t>(payload.size());
    idl::BackfillSample sample;
    idl::BackfillSamplePubSubType type;
    // False for a truncated buffer; Fast-CDR throws for other malformed input.
    try {
        if (!type.deserialize(&serialized, &sample))
            return std::nullopt;
    } catch (const std::exception&) {
        return std::nullopt;
    }
    return sample;
}

std::vector<std::pair<std::int64_t, std::int64_t>> row_ranges(std::vector<std::int64_t> rows) {
    std::sort(rows.begin(), rows.end());
    std::vector<std::pair<std::int64_t, std::int64_t>> ranges;
    for (const std::int64_t row : rows) {
        if (!ranges.empty() && row <= ranges.back().second + 1)
            ranges.back().second = std::max(ranges.back().second, row);
        else
            ranges.emplace_back(row, row);
    }
    return ranges;
}

}  // namespace tgw::wire
