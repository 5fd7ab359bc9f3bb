#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/drop_reason.hpp"

namespace tgw::basecamp {

/// One sample the base camp received, as the accounting needs it.
struct ReceivedSample {
    std::optional<std::uint32_t> sequence;  ///< PaperMessage sequence number, when the payload has one
    std::int64_t source_ns = 0;             ///< the publisher's source timestamp (wall clock)
    double transit_ms = 0.0;                ///< receive minus source timestamp
};

/// One row of the gateway's on-robot log (table `dropped_samples`), as the accounting needs it.
struct LoggedSample {
    std::string topic;
    std::optional<std::uint32_t> sequence;  ///< PaperMessage sequence number, when the payload has one
    std::int64_t source_ns = 0;
    std::string reason;  ///< expired, doomed, evicted, oversize, shutdown (or a name this build does not know)
};

/// Where every published sample of one topic went: received (on time or late), dropped by the gateway with its
/// reason, lost on the link, or unaccounted. Without a count of what left the robot, `lost_on_link` is inferred:
/// the gateway forwards, queues or logs every sample it takes in, so a sample neither received nor logged left
/// the robot and was lost on the way.
struct DropAccounting {
    std::optional<std::uint64_t> offered;  ///< samples published, when known
    std::uint64_t received = 0;            ///< distinct samples received
    std::optional<std::uint64_t> on_time;  ///< of `received`, within the TTL; empty when the TTL is unknown
    std::array<std::uint64_t, core::DROP_REASON_COUNT> dropped{};  ///< in the log and not received, by reason
    std::uint64_t dropped_other = 0;            ///< in the log, not received, with a reason this build does not know
    std::optional<std::uint64_t> lost_on_link;  ///< empty when neither `offered` nor a forwarded count is known
    bool lost_inferred = true;                  ///< false when the gateway's forwarded count was given
    std::optional<std::int64_t> unaccounted;    ///< offered - received - dropped - lost; may be negative
    std::uint64_t logged_and_received = 0;      ///< in the log and received as well: the two files disagree
    std::uint64_t duplicates_received = 0;      ///< the same sample recorded more than once (not counted twice)
    bool by_sequence = false;                   ///< matched by PaperMessage sequence, else by source timestamp

    std::uint64_t dropped_total() const;
};

/// Matches what the base camp received against what the gateway logged for one topic: by PaperMessage sequence
/// number when every sample on both sides has one, else by source timestamp (to the microsecond, +-1 us: both
/// sides went through RTPS time conversions). `offered`: samples published; `forwarded`: samples the gateway
/// wrote to the WAN (makes `lost_on_link` exact and `unaccounted` meaningful). Never throws.
DropAccounting account_topic(const std::vector<ReceivedSample>& received, const std::vector<LoggedSample>& logged,
                             std::optional<double> ttl_s, std::optional<std::uint64_t> offered,
                             std::optional<std::uint64_t> forwarded);

/// Reads the rows of the gateway's on-robot log whose source time is at or after `since_ns`. Throws
/// base::ConfigError naming `flag` and the file if it is not an on-robot log.
std::vector<LoggedSample> read_robot_log(const std::string& path, const std::string& flag, std::int64_t since_ns);

}  // namespace tgw::basecamp
