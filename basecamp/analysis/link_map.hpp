// The link-quality map (the paper's future work 7.5): where the robot was, what rate its link had there, and where
// samples stayed on the robot. Built from a recording or a mission archive (RecordingReader) as a SampleConsumer;
// drawn by render_link_map().
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "basecamp/sample/sample_consumer.hpp"
#include "types/type_library.hpp"

namespace tgw::basecamp {

/// Which topic holds the pose, and which members of it are x and y ("pose.position.x": a path through nested
/// structs).
struct PoseSource {
    std::string topic;
    std::string field_x = "x";
    std::string field_y = "y";

    /// "TOPIC" or "TOPIC:FIELD_X,FIELD_Y". Throws base::ConfigError naming `flag` when malformed.
    static PoseSource parse(const std::string& text, const std::string& flag);
};

struct MapPoint {
    std::int64_t time_ns = 0;  ///< the pose's source time
    double x = 0, y = 0;
};

/// One stretch of the path between two poses, at the rate the gateway sensed there (the last status before it).
struct MapSegment {
    MapPoint from, to;
    std::optional<double> rate_bps;  ///< nullopt before the first status
};

/// Where samples stayed on the robot: the mean of the poses at their source times, over a small square of the map,
/// and how many.
struct DropMark {
    double x = 0, y = 0;
    std::uint64_t samples = 0;
};

struct LinkMap {
    std::vector<MapSegment> segments;
    std::vector<DropMark> drops;
    double min_rate_bps = 0, max_rate_bps = 0;  ///< over the statuses; equal when there was one rate
    std::uint64_t poses = 0, rate_points = 0, dropped_samples = 0;
    std::string rates_from;  ///< "the gateway's log" or "the gateway's status"
    std::string drops_from;  ///< "the mission archive" or "the gateway's status counts"
};

/// Collects poses, the gateway's statuses and the samples dropped on the robot, then makes the map.
class LinkMapBuilder final : public SampleConsumer {
  public:
    LinkMapBuilder(PoseSource pose, types::TypeLibrary types);

    void add_topic(TopicRecord topic) override;
    void add(SampleRecord sample) override;
    /// The rate the gateway logged at `time_ns` (RecordingReader::link_rates()): where there are any, they colour
    /// the path instead of the statuses, which a weak link delays or drops.
    void add_logged_rate(std::int64_t time_ns, double rate_bps);

    /// Throws base::ConfigError naming `pose_flag` when no pose decoded (an absent topic, a member it lacks), or
    /// "FILE: no tgw/status" when there is no rate to colour the path with (neither logged nor in a status).
    LinkMap build(const std::string& pose_flag, const std::string& file) const;

  private:
    struct Status {
        std::int64_t time_ns;
        double rate_bps;
        std::uint64_t logged;  ///< the gateway's total of samples sent to its log so far
    };
    struct Drop {
        std::int64_t time_ns;
    };

    const PoseSource pose_;
    const types::TypeLibrary types_;
    mutable std::mutex mutex_;
    std::vector<MapPoint> poses_;
    std::vector<Status> statuses_;
    std::vector<Drop> archive_drops_;
    std::vector<Status> logged_rates_;
    std::string pose_error_;  ///< the first pose that did not decode, and why
    std::uint64_t pose_samples_ = 0;
};

}  // namespace tgw::basecamp
