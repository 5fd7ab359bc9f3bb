// The link-quality map as a picture: the robot's path in metres, coloured by the link rate the gateway sensed
// there (red slow, green fast), and a cross where samples stayed on the robot.
#pragma once

#include <string>

#include "basecamp/analysis/link_map.hpp"

namespace tgw::basecamp {

/// The colour of `rate_bps` between `min_bps` (red) and `max_bps` (green), through yellow; r, g, b in [0, 1].
struct Rgb {
    double r = 0, g = 0, b = 0;
};
Rgb rate_colour(double rate_bps, double min_bps, double max_bps);

/// Draws `map` into a PNG file at `path` (`width` x `height` pixels); `title` heads it. Throws base::ConfigError
/// naming `flag` and the file when it cannot be written.
void render_link_map(const LinkMap& map, const std::string& title, const std::string& path, const std::string& flag,
                     int width = 1200, int height = 900);

}  // namespace tgw::basecamp
