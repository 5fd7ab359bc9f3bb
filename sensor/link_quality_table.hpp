#pragma once

#include <istream>
#include <optional>
#include <string>
#include <vector>

namespace tgw::sensor {

/// Maps a link quality (as /proc/net/wireless reports it) to a data rate, as the paper mapped link strength to
/// rate: each row's rate holds from its quality up to the next row's. Below the first row there is no rate.
class LinkQualityTable {
  public:
    struct Row {
        double min_quality;
        double rate_bps;
    };

    /// `rows` must be non-empty with strictly increasing qualities and rates >= 0 (parse_link_quality_table checks).
    explicit LinkQualityTable(std::vector<Row> rows) : rows_(std::move(rows)) {}

    /// The built-in table, for a quality out of 70 (what most Linux Wi-Fi drivers report): a conservative guess at
    /// what 802.11g carries, about half the PHY rate at each step. Measure your radio and give your own table.
    ///   quality  0 ->   500 kbit/s    10 ->  1 Mbit/s    20 ->  2.5 Mbit/s   30 ->  5 Mbit/s
    ///   quality 40 ->    12 Mbit/s    50 -> 18 Mbit/s    60 ->   25 Mbit/s
    static LinkQualityTable default_table();

    /// The rate of the last row at or below `quality`; nullopt below the first row.
    std::optional<double> rate_for(double quality) const;

    const std::vector<Row>& rows() const { return rows_; }

  private:
    std::vector<Row> rows_;
};

/// Parses lines of `quality bits_per_second` (the rate may carry a k, M or G suffix); `#` starts a comment,
/// blank lines are allowed; qualities strictly increasing. Throws base::ConfigError "FILE:LINE: what is wrong".
LinkQualityTable parse_link_quality_table(std::istream& in, const std::string& file_name);

/// Opens `path` and parses it; throws base::ConfigError naming the file if it cannot be read or is malformed.
LinkQualityTable load_link_quality_table(const std::string& path);

}  // namespace tgw::sensor
