#include "wire/backfill_codec.hpp"

#include <gtest/gtest.h>

#include "gateway/dds/backfill_sender.hpp"

namespace tgw::dds {
namespace {

using namespace std::chrono_literals;

log::StoredSample a_row() {
    log::StoredSample row;
    row.row_id = 0x0102030405060708;
    row.topic = "telemetry/C";
    row.type_name = "tgw::idl::TelemetryC";
    row.payload = {0, 1, 0, 0, 42, 43, 44};
    row.key.valid = true;
    row.key.bytes.fill(0xAB);
    row.source_time = base::WallTime(1'700'000'000s);
    row.deadline = row.source_time + 5s;
    row.reason = "expired";
    return row;
}

TEST(BackfillCodecTest, ASampleComesBackAsItWasWithItsRowReadableWithoutDecoding) {
    const std::array<std::uint8_t, 16> log_id = *wire::log_id_octets("00112233445566778899aabbccddeeff");
    const std::vector<std::uint8_t> bytes = wire::encode_backfill(backfill_sample(a_row(), log_id));
    ASSERT_FALSE(bytes.empty());
    EXPECT_EQ(wire::backfill_row_id(bytes), 0x0102030405060708);
    const std::optional<idl::BackfillSample> sample = wire::decode_backfill(bytes);
    ASSERT_TRUE(sample);
    EXPECT_EQ(sample->row_id(), 0x0102030405060708u);
    EXPECT_EQ(sample->log_id(), log_id);
    EXPECT_EQ(sample->topic(), "telemetry/C");
    EXPECT_EQ(sample->type_name(), "tgw::idl::TelemetryC");
    EXPECT_EQ(sample->source_ns(), 1'700'000'000'000'000'000);
    EXPECT_EQ(sample->deadline_ns(), 1'700'000'005'000'000'000);
    EXPECT_EQ(sample->reason(), "expired");
    EXPECT_TRUE(sample->keyed());
    EXPECT_EQ(sample->instance()[15], 0xAB);
    EXPECT_EQ(sample->payload(), a_row().payload);
}

TEST(BackfillCodecTest, TheRowIdIsReadInEitherByteOrder) {
    std::vector<std::uint8_t> big = {0x00, 0x00, 0, 0, 0, 0, 0, 0, 0, 0, 0x01, 0x02};
    EXPECT_EQ(wire::backfill_row_id(big), 0x0102);
    std::vector<std::uint8_t> little = {0x00, 0x01, 0, 0, 0x02, 0x01, 0, 0, 0, 0, 0, 0};
    EXPECT_EQ(wire::backfill_row_id(little), 0x0102);
    EXPECT_FALSE(wire::backfill_row_id({0x00, 0x01, 0, 0, 1, 2, 3})) << "too short";
    EXPECT_FALSE(wire::backfill_row_id({0x00, 0x07, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8})) << "not plain CDR";
}

TEST(BackfillCodecTest, BytesThatAreNotASampleAreRefused) {
    EXPECT_FALSE(wire::decode_backfill({0x00, 0x01, 0, 0, 1}));
    EXPECT_FALSE(wire::decode_backfill({}));
}

TEST(BackfillCodecTest, ALogIdIsThirtyTwoHexCharacters) {
    const std::optional<std::array<std::uint8_t, 16>> octets = wire::log_id_octets("00112233445566778899AABBCCDDEEFF");
    ASSERT_TRUE(octets);
    EXPECT_EQ(wire::log_id_hex(*octets), "00112233445566778899aabbccddeeff");
    EXPECT_FALSE(wire::log_id_octets("00112233"));
    EXPECT_FALSE(wire::log_id_octets("zz112233445566778899aabbccddeeff"));
}

TEST(BackfillCodecTest, RowsBecomeSortedJoinedRanges) {
    using Ranges = std::vector<std::pair<std::int64_t, std::int64_t>>;
    EXPECT_EQ(wire::row_ranges({7, 3, 4, 5, 9, 5, 10, 1}), (Ranges{{1, 1}, {3, 5}, {7, 7}, {9, 10}}));
    EXPECT_EQ(wire::row_ranges({}), Ranges{});
}

}  // namespace
}  // namespace tgw::dds
