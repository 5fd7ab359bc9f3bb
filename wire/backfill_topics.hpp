#pragma once

#include <chrono>
#include <string_view>

namespace tgw::wire {

/// Backfill (idl/Backfill.idl): what the on-robot log kept crosses to the base camp on this topic, in capacity no
/// live sample wants. The camp stores it and never republishes it: it is past its TTL.
inline constexpr const char* BACKFILL_TOPIC = "tgw/backfill";
/// The backfill topic's TTL in the schedule: longer than any live topic's, so that it is the least urgent of all.
/// A sample of it waits for the link at most this long before its row goes back to the planner.
inline constexpr std::chrono::hours BACKFILL_TTL{1};
/// The base camp's acknowledgements of the backfilled rows it stored, back to the gateway.
inline constexpr const char* BACKFILL_ACK_TOPIC = "tgw/backfill_ack";

/// Backfill's own topics, which camp tools read with their own endpoints or not at all: a plain reader would
/// republish samples past their TTL, or have a gateway send rows no one acknowledges.
inline bool is_backfill_topic(std::string_view topic) {
    return topic == BACKFILL_TOPIC || topic == BACKFILL_ACK_TOPIC;
}

}  // namespace tgw::wire
