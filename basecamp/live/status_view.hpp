#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "GatewayStatus.h"
#include "base/time.hpp"
#include "basecamp/sample/sample_consumer.hpp"

namespace tgw::basecamp {

/// The gateways' status (tgw/status) as `tm-basecamp status` shows it: per gateway, the latest status and the
/// sensed rate over the last minutes. Fed by a Recorder; thread-safe.
class StatusView final : public SampleConsumer {
  public:
    /// `history`: how far back the rate graph goes.
    explicit StatusView(base::Duration history);

    void add_topic(TopicRecord /*topic*/) override {}
    void add(SampleRecord sample) override;

    /// Status samples taken so far (other topics and undecodable samples are not counted).
    std::uint64_t statuses() const;
    /// Undecodable samples of the status topic.
    std::uint64_t malformed() const;

    /// One screen: per gateway, the rate graph `columns` wide, then its figures and one line per topic.
    void render(std::ostream& out, std::int64_t now_ns, std::size_t columns = 60) const;

  private:
    struct RatePoint {
        std::int64_t at_ns;
        double rate_bps;
    };
    /// Backfill's acknowledged rows as one status gave them, at the gateway's time.
    struct AckPoint {
        std::int64_t at_ns;
        std::uint64_t acknowledged;
    };
    struct Gateway {
        idl::GatewayStatus latest;
        std::int64_t received_ns = 0;
        std::deque<RatePoint> rates;
        std::deque<AckPoint> acks;  ///< the last BACKFILL_RATE_WINDOW's
    };

    const std::int64_t history_ns_;
    mutable std::mutex mutex_;
    std::map<std::vector<std::uint8_t>, Gateway> gateways_;  // by WAN GUID prefix
    std::uint64_t statuses_ = 0;
    std::uint64_t malformed_ = 0;
};

/// `values` as one line of block characters from ' ' (no value) and '▁' (0) to '█' (`max`).
std::string sparkline(const std::vector<std::optional<double>>& values, double max);

}  // namespace tgw::basecamp
