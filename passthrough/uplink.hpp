// Commands back to the robot: samples the base camp publishes on listed topics, passed on while they are fresh.
// The gateway's --uplink takes them from the WAN into the robot domain; tm-basecamp relay --uplink from the camp's
// domain onto the WAN.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <fastdds/rtps/common/GuidPrefix_t.hpp>

#include "base/clock.hpp"
#include "core/wire_model.hpp"
#include "passthrough/discovery.hpp"
#include "passthrough/partition_groups.hpp"
#include "passthrough/ttl_resolver.hpp"

namespace eprosima::fastdds::dds {
class DomainParticipant;
}  // namespace eprosima::fastdds::dds

namespace tgw::passthrough {

/// What became of one uplink topic's samples: received = delivered + no_reader + expired + failed.
struct UplinkCount {
    std::string from_topic;  ///< its name where the commands come from (the WAN for the gateway)
    std::string to_topic;    ///< its name where they go (the robot domain for the gateway)
    std::string type_name;
    std::optional<ResolvedTtl> ttl;  ///< nullopt: they never expire (no Lifespan, and no other TTL given)
    std::uint64_t received = 0;      ///< taken, the uplink's own participant's writes aside
    std::uint64_t delivered = 0;     ///< written on the other side while a reader there had matched the writer
    std::uint64_t no_reader = 0;     ///< written while none had: gone to no one, unless the writer keeps history
    std::uint64_t expired = 0;       ///< at or past their deadline when they came: never delivered
    std::uint64_t failed = 0;        ///< the write failed
    std::uint64_t wire_bytes = 0;    ///< what they cost the link, as the wire model counts them
    std::int32_t writers = 0;        ///< writers its reader has matched now
    std::int32_t readers = 0;        ///< readers its writer has matched now
};

/// The routes of an uplink, one per listed topic once a publisher of it is discovered: a reader on the participant
/// the commands come from and a writer on the one they go to, of the publisher's type (passed through unread, as
/// the gateway's other topics are).
///
/// The writer offers what the first publisher offered (reliability, durability, partitions...) with the topic's TTL
/// as its Lifespan, and writes each sample with its source timestamp, so the readers see the command as it was
/// sent. A sample at or past its deadline when it comes is counted and dropped: a stale velocity command is worse
/// than none. The reader is best effort: on the WAN, a reliable base-camp writer then sends no repairs across the
/// link, which would come too late for a command anyway, and no acknowledgements go back. Every sample taken is
/// charged to the link budget (`charge`), for commands share the radio channel with the telemetry.
class Uplink {
  public:
    using Charge = std::function<void(std::uint64_t frame_bytes)>;

    /// Commands go from `from` to `to`, which must outlive the uplink. Samples of `from`'s own writers (a listed
    /// topic the gateway also bridges the other way) are never passed back. `charge` may be empty.
    Uplink(eprosima::fastdds::dds::DomainParticipant* from, eprosima::fastdds::dds::DomainParticipant* to,
           const base::Clock& clock, core::WireModel wire, Charge charge);
    ~Uplink();

    Uplink(const Uplink&) = delete;
    Uplink& operator=(const Uplink&) = delete;

    /// Routes `publisher`'s topic (a listed one) to `to_topic` with `ttl` (nullopt: its samples never expire),
    /// unless it is routed already. False, after logging it, when Fast DDS refuses the reader or the writer: nothing
    /// of the route stays.
    bool route(const DiscoveredPublisher& publisher, const std::string& to_topic,
               const std::optional<ResolvedTtl>& ttl);

    /// Deletes every route's reader and writer (before the robot participant goes); their counts stay, and
    /// nothing is routed from then on. Idempotent.
    void close();

    /// Every route's counts, by the topic's name where the commands come from.
    std::vector<UplinkCount> counts() const;

  private:
    class Route;

    eprosima::fastdds::dds::DomainParticipant* from_;
    eprosima::fastdds::dds::DomainParticipant* to_;
    const base::Clock& clock_;
    const core::WireModel wire_;
    const Charge charge_;
    const eprosima::fastrtps::rtps::GuidPrefix_t own_;
    PartitionGroups<eprosima::fastdds::dds::Subscriber> subscribers_;  // under mutex_
    PartitionGroups<eprosima::fastdds::dds::Publisher> publishers_;    // under mutex_
    mutable std::mutex mutex_;
    std::map<std::string, std::unique_ptr<Route>> routes_;  // by the from topic; under mutex_
    std::vector<UplinkCount> closed_counts_;                // under mutex_
    bool closed_ = false;                                   // under mutex_
};

}  // namespace tgw::passthrough
