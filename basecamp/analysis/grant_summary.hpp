// What a fleet's robots were granted, from the rounds of grants the relay recorded (tm-basecamp relay
// --channel-rate --out): `tm-basecamp report` prints it under the per-topic table.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace tgw::basecamp {

/// One robot's grants over a recording (or one gateway's, where unnamed).
struct RobotGrants {
    std::string robot;  ///< its --robot-name, else its gateway's prefix
    std::uint64_t rounds = 0;
    double min_bps = 0;
    double mean_bps = 0;
    double max_bps = 0;
    double last_bps = 0;
};

/// The channel the grants split, and each robot's share.
struct GrantSummary {
    std::uint64_t rounds = 0;
    double min_channel_bps = 0;
    double mean_channel_bps = 0;
    double max_channel_bps = 0;
    bool measured = false;            ///< the relay measured the channel (--measure-channel)
    std::vector<RobotGrants> robots;  ///< by name
};

/// Reads the `channel` and `grants` tables of a recording; nullopt when it has no round (the relay did not share a
/// channel, or the recording predates them). Throws base::ConfigError naming the file if it cannot.
std::optional<GrantSummary> read_grant_summary(const std::string& path);

/// The summary as `tm-basecamp report` prints it.
void print_grant_summary(std::ostream& out, const GrantSummary& summary);

}  // namespace tgw::basecamp
