// tm-basecamp relay: the base camp's one participant on the WAN domain, republishing every topic it carries
// into the camp's own domain, where any number of programs subscribe with their vendors' defaults.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include "base/clock.hpp"
#include "base/time.hpp"
#include "basecamp/capture/delivery_tally.hpp"
#include "basecamp/capture/discovery_queue.hpp"
#include "basecamp/channel/channel_grantor.hpp"
#include "basecamp/sample/sample_consumer.hpp"
#include "passthrough/discovery.hpp"
#include "passthrough/lane_assignment.hpp"
#include "passthrough/partition_groups.hpp"
#include "passthrough/type_object_guard.hpp"
#include "passthrough/uplink.hpp"
#include "passthrough/uplink_topics.hpp"

namespace eprosima::fastdds::dds {
class DomainParticipant;
class Publisher;
class Subscriber;
}  // namespace eprosima::fastdds::dds

namespace tgw::basecamp {

class BackfillArchive;
class BackfillEndpoints;
class CompactUnpacker;
class ReceiverReporter;

/// Subscribes on the WAN domain to every topic that appears there, whatever its type, asking exactly what each
/// writer offers (reliability, durability, partitions, ownership, representation), and writes every sample on
/// the local domain under the same topic and type name, with its source timestamp and instance, through a
/// writer that offers the same QoS and the same Lifespan (so the sample expires there when it would have at
/// the robot). A transient-local ("latched") topic's last sample per instance stays in the local writer, so a
/// program that joins later gets it from there, at no cost to the radio. Disposes and unregisters pass too.
///
/// Like the gateway, it makes one lane per QoS offer of a topic (a reader on the WAN, a writer on the local
/// domain), and a writer's samples are passed on by its own lane only.
///
/// The other way, only the `uplink` topics (commands: rt/NAME/cmd_vel) go from the camp's domain onto the WAN, to
/// the gateways' --uplink: published on the WAN under the same name and type, with the camp publisher's QoS,
/// source timestamps and Lifespan; a command already past its Lifespan is dropped here and never costs the link.
class Relay {
  public:
    /// Creates both participants: on `wan_domain` with `wan_qos` (made for the link: base::apply_peer_transport), on
    /// `local_domain` with `local_qos` (Fast DDS's defaults: multicast discovery, shared memory and UDP, perhaps
    /// bound to one interface). With `store`, every sample taken off the WAN goes there too: a recording, as `record`
    /// makes, a Foxglove server, or both. Every `report_period` (zero: never) it tells each gateway what arrived and
    /// what was lost on the way, as `record` does: the camp's one WAN participant is the one to report. Throws
    /// base::ConfigError naming the flag when DDS refuses a participant. `uplink`: the topics the camp's programs
    /// may publish onto the WAN (exact names); none by default. `channel_bps`: the rate of the channel a fleet
    /// shares, which the relay grants the gateways in shares (ChannelGrantor); 0: no grants. `measure_channel`: the
    /// channel's rate is measured from what arrives, `channel_bps` its upper bound (core::ChannelEstimate).
    Relay(int wan_domain, eprosima::fastdds::dds::DomainParticipantQos wan_qos, int local_domain,
          eprosima::fastdds::dds::DomainParticipantQos local_qos, SampleConsumer* store = nullptr,
          base::Duration report_period = std::chrono::seconds(1), const std::vector<std::string>& uplink = {},
          double channel_bps = 0, bool measure_channel = false);
    ~Relay();
    Relay(const Relay&) = delete;
    Relay& operator=(const Relay&) = delete;

    /// Backfill (docs/design/backfill.md): the gateways' backfilled samples go into `archive` (never onto the local
    /// domain) and its acknowledgements back to them. Without it, backfill is not read, and no gateway sends it.
    /// Throws base::ConfigError when DDS refuses an entity. `archive` must outlive the relay.
    void archive_backfill(BackfillArchive& archive);

    /// Makes the WAN participant anew with `wan_qos` (an address that changed, a peer's name that resolves to
    /// another): everything on the WAN goes and comes back as the gateways are discovered again, while the local
    /// participant and the lanes' local writers stay, so the camp's programs keep their readers matched and a
    /// latched topic's last samples. In compact mode the unpacker is made anew, its local writers with it. Not
    /// while run() runs. Throws base::ConfigError when DDS refuses the participant: the relay then has none on the
    /// WAN (the camp's domain stays) until a later remake_wan() makes one.
    void remake_wan(eprosima::fastdds::dds::DomainParticipantQos wan_qos);

    /// Creates lanes for topics as they are discovered, until `duration` has passed or `stop` turns true.
    void run(base::Duration duration, const std::atomic<bool>& stop);

    /// Readers on the local domain matched with the topic's writers now.
    std::int32_t local_readers(const std::string& topic) const;

    /// Samples (and disposes, unregisters) written on the local domain so far, per topic.
    std::map<std::string, std::uint64_t> relayed() const;

    /// The shares of the channel last granted, by gateway prefix (hex); empty without a channel rate.
    core::ChannelGrants channel_grants() const;
    /// The newcomers' share last granted (ChannelGrantor::newcomer_share); nullopt without a channel rate.
    std::optional<double> newcomer_share() const;
    /// What the measure of the channel found (ChannelMeter); nullopt without --measure-channel.
    std::optional<ChannelReading> channel_reading() const;

    /// The uplink topics a camp publisher was discovered of, with what became of their samples.
    std::vector<passthrough::UplinkCount> uplink_counts() const;

    /// What the compact WAN mode's unpacker has done; nullptr until a compact-mode gateway appeared.
    const CompactUnpacker* compact() const { return compact_.get(); }

  private:
    class Lane;
    struct Topic {
        passthrough::LaneAssignment writers;
        std::vector<std::unique_ptr<Lane>> lanes;
    };

    /// The WAN participant and what lives on it alone (the reports, the grants); the uplink and backfill after.
    void make_wan(eprosima::fastdds::dds::DomainParticipantQos wan_qos);
    /// The uplink's routes, and the camp's publishers already routed: a remade WAN participant routes them again.
    void make_uplink();
    /// Deletes the WAN participant and everything on it; the lanes keep their local writers.
    void retire_wan();
    void relay(const passthrough::DiscoveredPublisher& publisher);
    /// The WAN reader of `lane`, which takes `publisher`'s topic with its QoS; false when DDS refuses it.
    bool attach_reader(Lane& lane, const passthrough::DiscoveredPublisher& publisher);
    /// Routes a camp publisher of an uplink topic onto the WAN, and remembers it; others are ignored.
    void uplink(const passthrough::DiscoveredPublisher& publisher);
    void route_uplink(const passthrough::DiscoveredPublisher& publisher);
    std::unique_ptr<Lane> make_lane(const passthrough::DiscoveredPublisher& publisher, Topic& topic,
                                    std::uint16_t index);

    SampleConsumer* store_;
    const int wan_domain_;
    const double channel_bps_;
    const bool measure_channel_;
    bool wan_secured_ = false;  ///< the WAN participant runs DDS Security: the uplink's wire model counts it
    DeliveryTally tally_;
    /// With --measure-channel: what the WAN transport receives (shared with it), for the grantor.
    std::shared_ptr<ChannelMeter> meter_;
    base::Duration report_period_;
    /// Kept across run() calls, so that a caller may run in slices.
    base::SteadyTime next_report_ = base::SteadyClock::now() + report_period_;
    std::unique_ptr<ReceiverReporter> reporter_;
    DiscoveryQueue discovered_;  ///< before discovery_, whose callback feeds it
    std::unique_ptr<passthrough::Discovery> discovery_;
    eprosima::fastdds::dds::DomainParticipant* wan_ = nullptr;
    const passthrough::UplinkTopics uplink_topics_;  ///< exact names, the same on both sides
    DiscoveryQueue local_discovered_;                ///< before local_discovery_, whose callback feeds it
    /// The local participant's listener: the camp's publishers of uplink topics (and it keeps the TypeObjects that
    /// base-camp tools announce from Fast DDS, as every listener of the project does).
    std::unique_ptr<passthrough::Discovery> local_discovery_;
    eprosima::fastdds::dds::DomainParticipant* local_ = nullptr;
    passthrough::PartitionGroups<eprosima::fastdds::dds::Subscriber> wan_subscribers_;
    passthrough::PartitionGroups<eprosima::fastdds::dds::Publisher> local_publishers_;
    /// Made when a compact-mode gateway's bundles or catalog appear; before the participants go.
    std::unique_ptr<CompactUnpacker> compact_;
    base::SystemClock clock_;
    std::unique_ptr<passthrough::Uplink> uplink_;  ///< with uplink topics; before the participants go
    std::vector<passthrough::DiscoveredPublisher> uplink_publishers_;  ///< the camp's, routed onto the WAN
    std::unique_ptr<ChannelGrantor> grantor_;      ///< with a channel rate; its writer is the WAN participant's
    std::unique_ptr<BackfillEndpoints> backfill_;  ///< with an archive; before the participants go
    BackfillArchive* archive_ = nullptr;           ///< see archive_backfill; the compact unpacker's too
    mutable std::mutex topics_mutex_;              ///< run() adds to topics_, relayed() reads it
    std::map<std::string, std::unique_ptr<Topic>> topics_;
    /// What the compact unpackers of WAN participants made anew before relayed, per topic; under topics_mutex_.
    std::map<std::string, std::uint64_t> relayed_by_earlier_unpackers_;
};

}  // namespace tgw::basecamp
