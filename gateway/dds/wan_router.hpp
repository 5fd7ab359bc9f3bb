#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fastdds/rtps/transport/TransportDescriptorInterface.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "base/clock.hpp"
#include "base/discovery_server.hpp"
#include "base/security_files.hpp"
#include "base/wan_address.hpp"
#include "core/sample.hpp"
#include "core/wire_model.hpp"
#include "gateway/dds/coalescing_transport.hpp"
#include "gateway/dds/datagram_coalescer.hpp"
#include "gateway/dds/wan_writer.hpp"
#include "passthrough/discovery.hpp"
#include "passthrough/offered_qos.hpp"
#include "passthrough/partition_groups.hpp"

namespace tgw::dds {

/// The smallest WAN datagram limit (WanConfig::max_datagram_bytes) with DDS Security, and its default then. Fast DDS
/// 2.9 sizes its authentication messages' buffers by the participant's largest message and fails to serialize a
/// handshake that does not fit ("Cannot serialize ParticipantGenericMessage", and no one is ever authenticated). The
/// handshake carries the certificate and the signed permissions: with scripts/make-certs' files its messages were
/// 5,550 and 5,730 bytes on loopback, a 4,500-byte limit failed and 8,192 passed. Samples up to this size then
/// leave as one datagram in IP fragments, which WireModel counts.
constexpr std::size_t SECURE_MIN_DATAGRAM_BYTES = 8192;

/// How the WAN participant reaches the base camp.
struct WanConfig {
    int domain = 1;
    std::vector<base::WanPeer> peers;
    /// A Fast DDS Discovery Server to be a client of, instead of announcing to `peers`.
    std::optional<base::DiscoveryServerAddress> discovery_server;
    /// IPv4 address to bind to (see resolve_interface_address); empty: every interface.
    std::string interface_address;
    /// Own metatraffic unicast port; 0: the well-known port of the participant id Fast DDS assigns.
    std::uint16_t listen_port = 0;
    /// SPDP, unless a participant profile is given: how long the peer keeps us without hearing from us, and
    /// how often we announce. Fast DDS's
    /// 20 s / 3 s put 5,300 bit/s on the link with one idle peer (docs/design.md §4); these cut that ~7x.
    std::chrono::seconds lease_duration{120};
    std::chrono::seconds announcement_period{20};
    /// The UDP transport the participant sends through, under its coalescer; its maxMessageSize is set to
    /// max_datagram_bytes. None: Fast DDS's UDPv4 transport. The integration tests give Fast DDS's
    /// test_UDPv4Transport, which loses the datagrams they choose, as a radio does.
    std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface> datagram_transport;
    /// The UDP transport's maxMessageSize: larger samples go as DATA_FRAG. One Ethernet frame by default;
    /// the scheduler's WireModel must be made for the same size.
    std::size_t max_datagram_bytes = core::WireModel::MAX_DATAGRAM_PAYLOAD_BYTES;
    /// A sample written within this long of the previous datagram to the same destination waits, at most this
    /// long, to share a datagram with those that follow (DatagramCoalescer); one that comes alone goes at once.
    /// 0: one datagram per sample.
    std::chrono::microseconds coalesce_window = DatagramCoalescer::DEFAULT_WINDOW;
    /// A reliable writer puts a HEARTBEAT (32 bytes) in a sample's message once it has sent this many bytes
    /// since its last one, and each HEARTBEAT brings an ACKNACK back from every reader. 0: one with every
    /// sample, as Fast DDS does by default, so a lost sample is repaired one sample later. Between them the
    /// writer's periodic HEARTBEAT (3 s) covers a quiet writer.
    std::uint32_t heartbeat_spacing_bytes = DEFAULT_HEARTBEAT_SPACING_BYTES;
    /// Sends every RTPS message without the statistics submessage this Fast DDS build ends it with (60 bytes; only
    /// eProsima's statistics module reads it): WireModel::without_statistics() must then be the model.
    bool strip_statistics = false;
    /// Sends without it every message that carries no application's sample (HEARTBEATs, ACKNACKs and GAPs alone,
    /// discovery): 60 of the 170 bytes of a lone HEARTBEAT. The samples keep it for a base camp's channel meter.
    bool strip_statistics_without_samples = true;
    /// How long a reliable writer's HEARTBEATs or GAPs alone wait for the next message to the same destination, to
    /// ride in its datagram (DatagramCoalescer::hold); 0 sends them at once.
    base::Duration control_wait = DatagramCoalescer::DEFAULT_CONTROL_WAIT;
    /// Sends a message to one participant without the INFO_DST that names it (16 bytes; its unicast locators
    /// reach that participant alone): WireModel::without_destination() must then be the model. Leave it off
    /// with security, which signs the message as Fast DDS made it.
    bool strip_destination = false;
    /// Leave out the INFO_TS of a one-sample message written inside an UnstampedWrite (compact mode's bundles,
    /// which hold their write time): WireModel::without_timestamp() must then be the model. Leave it off with
    /// security, as strip_destination.
    bool strip_timestamp = false;
    /// DDS Security (--wan-security): the identity whose checked files the participant authenticates with, and
    /// the governance and permissions it follows; none: a plain participant.
    std::optional<base::SecurityFiles> security;
    /// What the participant sends beyond the scheduled writes (see CoalescingTransport), so the caller can
    /// charge it to the link budget.
    UnscheduledTrafficCallback on_unscheduled;
    /// A reliable reader's repairs of a sample the gateway wrote wait for the schedule (RepairDesk) instead of
    /// leaving at once; the caller must give the desk somewhere to submit them.
    bool schedule_repairs = false;
    /// The participant's announcements wait for the schedule too (RepairDesk::hold_announcement), in either mode;
    /// the caller must give the desk somewhere to submit them.
    bool schedule_announcements = false;
    /// A reliable writer's HEARTBEAT leaves only with a sample's last fragment (without_early_heartbeats).
    bool strip_early_heartbeats = true;
    /// Every base-camp writer the participant discovers (the uplink's commands), from Fast DDS's discovery thread:
    /// it must return quickly and create no entities. None: they are not reported.
    std::function<void(passthrough::DiscoveredPublisher&&)> on_remote_publisher;
    /// With a discovery server: a plain client hears only of endpoints of its own topics. A super client hears of
    /// every one, which the uplink needs to learn a command's type from its publisher.
    base::DiscoveryRole discovery_role = base::DiscoveryRole::client;
};

/// The gateway's participant on the WAN domain: UDPv4 unicast only (no multicast, no shared memory), bound to
/// one interface, announcing itself to the configured peers' exact ports, with long announcement periods.
/// It makes the WanWriter of each lane of a bridged topic (one per QoS its robot publishers offer, OfferedQos),
/// with the robot topic's name and type name, offering what the publishers offered, in their partitions, and
/// the Lifespan the gateway chose; the topic's TopicBridge holds them. A transient-local ("latched") lane keeps the
/// last sample of each instance for readers that join later; what it sends them then is unscheduled traffic
/// (WanConfig::on_unscheduled). It reads one topic only: the base camp's receiver reports, when asked to.
class WanRouter {
  public:
    /// Throws base::ConfigError when the participant cannot be created. `base`: starting QoS (an XML
    /// participant profile) or nullopt for Fast DDS's default; transports, locators and discovery periods
    /// are then set from `config`.
    WanRouter(const WanConfig& config, const std::optional<eprosima::fastdds::dds::DomainParticipantQos>& base);
    ~WanRouter();

    WanRouter(const WanRouter&) = delete;
    WanRouter& operator=(const WanRouter&) = delete;

    /// The data_writer profile named after `topic` in the loaded XML files, if there is one.
    std::optional<eprosima::fastdds::dds::DataWriterQos> writer_profile(const std::string& topic) const;

    /// A writer of `wan_topic` offering `offer`, with Lifespan `lifespan` (nullopt: infinite), announcing the type
    /// with the robot publisher's TypeObject `announced` (see passthrough_topic()); `topic` names its data_writer
    /// profile (the robot's name of the topic, which --robot-name may change on the WAN). nullptr (after logging
    /// it) when Fast DDS refuses. Every writer must be released before the router goes.
    std::shared_ptr<WanWriter> create_writer(
        const std::string& topic, const std::string& wan_topic, const std::string& type_name, bool keyed,
        std::optional<base::Duration> lifespan, const passthrough::OfferedQos& offer,
        const std::shared_ptr<const eprosima::fastrtps::types::TypeObject>& announced);

    /// Creates a reader of wire::RECEIVER_REPORT_TOPIC for `listener`, which must outlive the router. False
    /// (after logging it) when Fast DDS refuses.
    bool subscribe_receiver_reports(eprosima::fastdds::dds::DataReaderListener* listener);
    /// Creates a reader of wire::CHANNEL_GRANT_TOPIC for `listener`, which must outlive the router. False (after
    /// logging it) when Fast DDS refuses.
    bool subscribe_grants(eprosima::fastdds::dds::DataReaderListener* listener);
    /// Creates a reader of wire::BACKFILL_ACK_TOPIC for `listener`, which must outlive the router: reliable, as the
    /// camp writes them (each tells what is new since the last). False (after logging it) when Fast DDS refuses.
    bool subscribe_backfill_acks(eprosima::fastdds::dds::DataReaderListener* listener);

    /// Base-camp participants discovered now.
    std::size_t remote_participants() const;
    /// The participant, for the uplink's readers (Uplink), which it must outlive.
    eprosima::fastdds::dds::DomainParticipant* participant() const { return participant_; }
    /// How the samples' datagrams were packed.
    const DatagramCoalescer& coalescer() const { return *coalescer_; }
    /// Where the participant's repairs of scheduled samples and its announcements wait for the schedule
    /// (WanConfig::schedule_repairs, schedule_announcements); null when they go at once.
    RepairDesk* repair_desk() const { return repair_desk_.get(); }
    /// Announcements sent again to participants that had not answered (IntroductionSchedule), and when the link
    /// came back (announce_again).
    std::uint64_t introductions() const;
    /// Announces the participant to its peers at once, from the introducer's thread: the link is up again, and
    /// the announcements made while it was down were lost (a base camp would hear of us at its next periodic
    /// one, or ours, many seconds later).
    void announce_again();
    /// Makes the participant anew, bound to `interface_address` (the WAN interface came back with another, a
    /// DHCP lease or a mesh radio's): the old one announced an address nobody can reach. Every writer made here
    /// gets its successor on the new participant (the same WanWriter; a transient-local lane's successor is given
    /// each instance's last change again), the receiver reports and grants are read again, and the new participant
    /// announces itself
    /// to the peers. Its GUID is new: the base camp sees a new participant, and lets the old one's lease run
    /// out. Call while nothing is scheduled (the link is down, the budget 0): writes in between fail. False
    /// (after logging it) when Fast DDS refuses; writes fail until a later rebind succeeds.
    bool rebind(const std::string& interface_address);
    /// The same, announcing to `peers` from now on (a peer given by name whose address came or changed).
    bool rebind(const std::string& interface_address, const std::vector<base::WanPeer>& peers);
    /// The peers the participant announces itself to.
    std::vector<base::WanPeer> peers() const;
    /// The address the participant is bound to now; empty: every interface.
    std::string interface_address() const;

    /// Repeated HEARTBEATs and ACKNACKs the transport held back (RepeatThrottle).
    std::uint64_t suppressed_repeats() const { return repeat_throttle_->suppressed(); }

    eprosima::fastrtps::rtps::GuidPrefix_t guid_prefix() const;

    /// Topics of the writers made here that the participant has now: each goes with its last writer, so topics
    /// that come and go leave none behind.
    std::size_t topic_count() const;

  private:
    class Introducer;
    class ParticipantCounter;

    /// What create_writer was asked, to make a writer's successor on a new participant.
    struct WriterRecipe {
        std::weak_ptr<WanWriter> writer;
        std::string topic;
        std::string wan_topic;
        std::string type_name;
        bool keyed = false;
        std::optional<base::Duration> lifespan;
        passthrough::OfferedQos offer;
        std::shared_ptr<const eprosima::fastrtps::types::TypeObject> announced;
    };

    std::optional<eprosima::fastdds::dds::DataWriterQos> writer_profile_nts(const std::string& topic) const;
    /// Creates participant_ and publisher_ from qos_, bound to `interface_address`; false when Fast DDS refuses.
    /// Under mutex_.
    bool create_participant_nts(const std::string& interface_address);
    /// Deletes participant_ and everything on it. Under mutex_.
    void delete_participant_nts();
    /// A DataWriter as `recipe` says, with `listener`; nullptr (after logging it) when Fast DDS refuses. Under
    /// mutex_.
    eprosima::fastdds::dds::DataWriter* create_datawriter_nts(const WriterRecipe& recipe,
                                                              eprosima::fastdds::dds::DataWriterListener* listener);

    /// A reader of `topic_name` for `listener`: with `reliable_depth` 0, best effort and the latest sample per
    /// instance; else reliable, keeping that many per instance.
    bool subscribe(const char* topic_name, eprosima::fastdds::dds::TypeSupport type,
                   eprosima::fastdds::dds::DataReaderListener* listener, std::int32_t reliable_depth = 0);
    /// Deletes `writer`, and its topic when it was the topic's last writer.
    void delete_writer(eprosima::fastdds::dds::DataWriter* writer);
    /// Deletes `topic` if no writer of ours uses it (a writer that could not be made left it behind). Under mutex_.
    void drop_unused_topic_nts(eprosima::fastdds::dds::Topic* topic);

    base::SystemClock clock_;  // datagrams wait in real time, whatever clock the scheduler runs on
    std::shared_ptr<DatagramCoalescer> coalescer_;
    std::shared_ptr<RepeatThrottle> repeat_throttle_ = std::make_shared<RepeatThrottle>();
    std::shared_ptr<RepairDesk> repair_desk_;
    const int domain_;
    eprosima::fastdds::dds::DomainParticipantQos qos_;  ///< all but the locators, which the address sets
    std::uint16_t listen_port_ = 0;
    mutable std::mutex mutex_;
    std::string interface_address_;     // under mutex_
    std::vector<base::WanPeer> peers_;  // under mutex_
    eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
    eprosima::fastdds::dds::Publisher* publisher_ = nullptr;                      ///< the default partition's
    passthrough::PartitionGroups<eprosima::fastdds::dds::Publisher> publishers_;  // under mutex_
    std::map<std::string, int> writers_of_topic_;                                 // under mutex_
    std::vector<WriterRecipe> recipes_;                                           // under mutex_; of the writers alive
    std::set<eprosima::fastdds::dds::DataWriter*> live_writers_;                  // under mutex_: of participant_
    std::vector<std::function<bool()>> subscriptions_;                            ///< subscribe's calls, to make again
    std::unique_ptr<Introducer> introducer_;            ///< stopped before participant_'s deletion
    std::unique_ptr<ParticipantCounter> participants_;  ///< before participant_'s deletion
};

}  // namespace tgw::dds
