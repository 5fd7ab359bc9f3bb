#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "basecamp/analysis/report.hpp"

namespace tgw::basecamp {

/// How much of a link's rate went to samples that arrived in time: the serialized bytes of the robot's samples
/// (the gateway's own tgw/ topics left out) that arrived within their TTL, counted by arrival over the steady
/// window. The window runs from STEADY_START after the first source time to STEADY_END_MARGIN before the last,
/// so that neither the queues filling at the start nor their drain at the end counts.
struct OnTimePayload {
    static constexpr double STEADY_START_S = 10.0;
    static constexpr double STEADY_END_MARGIN_S = 5.0;

    double window_start_s = 0.0;  ///< after the first source time
    double window_end_s = 0.0;
    std::uint64_t samples = 0;
    std::uint64_t bytes = 0;
    double bits_per_s = 0.0;
    double link_rate_bps = 0.0;

    double percent_of_link() const { return link_rate_bps > 0.0 ? 100.0 * bits_per_s / link_rate_bps : 0.0; }
};

/// Reads the recording's samples from `since_ns` on, judged by the TTLs the report resolved per topic. Empty when
/// the recording spans no steady window (less than STEADY_START_S + STEADY_END_MARGIN_S of source times). Throws
/// base::ConfigError naming the file if it cannot read it.
std::optional<OnTimePayload> read_on_time_payload(const std::string& path, const std::vector<TopicReport>& reports,
                                                  std::int64_t since_ns, double link_rate_bps);

/// One line: the figure, its window and the link rate it is held against; or why there is none.
void print_on_time_payload(std::ostream& out, const std::optional<OnTimePayload>& payload, double link_rate_bps);

}  // namespace tgw::basecamp
