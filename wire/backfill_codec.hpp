// The backfill topics' samples as bytes (idl/Backfill.idl), for the gateway that writes them through its scheduler
// and the base camp that reads them.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "BackfillPubSubTypes.h"

namespace tgw::wire {

/// A log's id (RobotLog::log_id, 32 hex characters) as the 16 octets the wire carries; nullopt when it is not one.
std::optional<std::array<std::uint8_t, 16>> log_id_octets(const std::string& hex);
/// The 32 lowercase hex characters of a log id's octets.
std::string log_id_hex(const std::array<std::uint8_t, 16>& octets);

/// `sample` serialized (encapsulation header included); empty when the type refuses it.
std::vector<std::uint8_t> encode_backfill(const idl::BackfillSample& sample);
/// The row id of a serialized idl::BackfillSample, read where it sits (its first member) without decoding the rest;
/// nullopt for bytes too short or of an encapsulation other than plain CDR.
std::optional<std::int64_t> backfill_row_id(const std::vector<std::uint8_t>& payload);
/// A serialized idl::BackfillSample; nullopt for bytes that are not one.
std::optional<idl::BackfillSample> decode_backfill(const std::vector<std::uint8_t>& payload);

/// Rows of one log as the ranges an acknowledgement carries: sorted, duplicates merged, neighbours joined.
std::vector<std::pair<std::int64_t, std::int64_t>> row_ranges(std::vector<std::int64_t> rows);

}  // namespace tgw::wire
