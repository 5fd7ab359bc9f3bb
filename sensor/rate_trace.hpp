#pragma once

#include <istream>
#include <string>
#include <vector>

#include "gateway/core/time.hpp"

namespace tgw::sensor {

/// A link rate over time read from a trace file, as steps. Each step's rate holds from its time until the next
/// step's time. Before the first step, the first step's rate holds (a trace that starts at 5 s still has a rate
/// at 0 s); after the last step, the last rate holds forever.
class RateTrace {
  public:
    struct Step {
        core::Duration at;  ///< since the start of the trace
        double rate_bps;
    };

    /// `steps` must be non-empty, with strictly increasing times and rates >= 0 (parse_rate_trace checks this).
    explicit RateTrace(std::vector<Step> steps) : steps_(std::move(steps)) {}

    /// The rate of the last step at or before `elapsed`; the first step's rate before the first step.
    double rate_at(core::Duration elapsed) const;

    const std::vector<Step>& steps() const { return steps_; }

  private:
    std::vector<Step> steps_;
};

/// Parses lines of `seconds bits_per_second` (both non-negative numbers; the rate may carry a k, M or G suffix).
/// `#` starts a comment to the end of the line; blank lines and CRLF line ends are allowed. Times must be strictly
/// increasing. Throws core::ConfigError "FILE:LINE: what is wrong" naming `file_name`, or "FILE: ..." if the trace
/// has no step at all.
RateTrace parse_rate_trace(std::istream& in, const std::string& file_name);

/// Opens `path` and parses it; throws core::ConfigError naming the file if it cannot be read or is malformed.
RateTrace load_rate_trace(const std::string& path);

}  // namespace tgw::sensor
