// What the base camp keeps of a topic and of each sample it receives: a recording's rows, and what live tools
// (stats, echo) are given; and, where it shares a fleet's channel, each round of grants.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tgw::basecamp {

/// A topic as discovery described its writer.
struct TopicRecord {
    std::string topic;
    std::string type_name;
    std::optional<std::int64_t> lifespan_ns;  ///< the writer's declared Lifespan; empty when infinite
    bool keyed = false;
    bool reliable = false;
    std::int64_t discovered_ns = 0;  ///< wall clock
    /// IDL of the type from the TypeObject its writer announced (passthrough::type_object_idl), when it described the
    /// type by itself; empty otherwise.
    std::string announced_idl;
};

/// Where a backfilled sample comes from: the on-robot log row it was kept in because the gateway could not send it
/// within its TTL. (log_id, row_id) names that row for ever, so the camp stores it once however often it arrives.
struct BackfillOrigin {
    std::string log_id;       ///< the on-robot log's id, 32 lowercase hex characters
    std::int64_t row_id = 0;  ///< the row's id in that log
    std::string reason;       ///< why it stayed on the robot, as the log says it: expired, doomed, no_reader, ...
};

/// One received sample. Times are wall clock, nanoseconds since the Unix epoch.
struct SampleRecord {
    std::string topic;
    std::string type_name;
    std::vector<std::uint8_t> payload;  ///< serialized, as received, encapsulation header included
    std::int64_t source_ns = 0;
    std::int64_t receive_ns = 0;
    std::optional<std::int64_t> lifespan_ns;
    std::vector<std::uint8_t> instance;  ///< 16-byte instance handle of keyed topics, else empty
    /// The on-robot log row it was backfilled from; empty for a live sample. A backfilled sample's receive_ns is
    /// when it reached the camp, its source_ns its source time.
    std::optional<BackfillOrigin> backfill;
};

/// One gateway's share in a round of grants.
struct GrantRecord {
    std::string gateway;  ///< its participant's GUID prefix, hex
    std::string robot;    ///< its --robot-name, or empty
    double rate_bps = 0;
};

/// One round of a fleet's grants (tm-basecamp relay --channel-rate): the channel's rate they split, what the camp
/// measured of it (--measure-channel), and each gateway's share. Wall clock, nanoseconds since the Unix epoch.
struct ChannelRecord {
    std::int64_t time_ns = 0;
    double channel_bps = 0;                   ///< told (--channel-rate), or measured
    double newcomer_bps = 0;                  ///< the share of any gateway without its own
    std::string verdict;                      ///< core::ChannelVerdict as text; empty when the channel is not measured
    std::optional<double> delivered_bps;      ///< what the channel delivered lately, where measured
    std::optional<std::int64_t> queueing_ns;  ///< its standing queue, where measured
    std::vector<GrantRecord> grants;
};

}  // namespace tgw::basecamp
