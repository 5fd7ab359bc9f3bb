#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "base/time.hpp"
#include "basecamp/sample/sample_consumer.hpp"
#include "basecamp/status/topic_robots.hpp"

namespace tgw::basecamp {

/// One topic's line of `tm-basecamp stats`: its samples in the window, and what the gateways' status says of it.
struct TopicStatsRow {
    std::string topic;
    std::string robot;  ///< whose gateway bridges it, per the gateways' status; empty when unnamed or unknown
    std::uint64_t window_samples = 0;
    double hz = 0.0;                ///< from the intervals between the window's samples, as `ros2 topic hz`
    double bit_per_s = 0.0;         ///< serialized payload (encapsulation included) over the window, as `ros2 topic bw`
    std::optional<double> mean_ms;  ///< transmission time: reception - the publisher's source timestamp
    std::optional<double> p99_ms;
    std::optional<double> ttl_s;                   ///< the writer's Lifespan, else the TTL a gateway's status gives
    std::optional<double> on_time_pct;             ///< of the window's samples, transmission time <= TTL
    std::optional<std::uint64_t> logged_on_robot;  ///< per the latest status of each gateway that bridges it
    std::uint64_t total_samples = 0;               ///< since the start
};

/// Live per-topic statistics over a sliding window of reception time, fed by a Recorder; the gateways' status
/// samples (tgw/status) among them give each topic's TTL and what its gateway logged instead of sending.
/// Thread-safe.
class TopicStats final : public SampleConsumer {
  public:
    explicit TopicStats(base::Duration window);

    void add_topic(TopicRecord topic) override;
    void add(SampleRecord sample) override;

    /// Every topic seen, by name, over the window that ends at `now_ns` (wall clock).
    std::vector<TopicStatsRow> rows(std::int64_t now_ns) const;

  private:
    struct Received {
        std::int64_t receive_ns;
        std::int64_t transmission_ns;
        std::size_t bytes;
    };
    struct Topic {
        std::optional<std::int64_t> lifespan_ns;
        std::int64_t first_receive_ns = 0;
        std::deque<Received> window;
        std::uint64_t total = 0;
    };
    /// What one gateway's latest status says of one topic.
    struct RobotSide {
        std::uint32_t ttl_ms = 0;
        std::uint64_t logged = 0;
    };

    void take_status_nts(const SampleRecord& sample);

    const std::int64_t window_ns_;
    mutable std::mutex mutex_;
    std::map<std::string, Topic> topics_;
    std::map<std::vector<std::uint8_t>, std::map<std::string, RobotSide>> by_gateway_;  // by GUID prefix
    TopicRobots robots_;
};

/// The table: topic, Hz, bit/s, mean and p99 transmission time, TTL, % within it, logged on the robot, total,
/// and the robot where a gateway named one (a fleet). "-" where a figure is unknown.
void print_stats_table(std::ostream& out, const std::vector<TopicStatsRow>& rows);

}  // namespace tgw::basecamp
