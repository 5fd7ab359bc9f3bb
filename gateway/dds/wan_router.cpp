#include "gateway/dds/wan_router.hpp"

#include <algorithm>
#include <condition_variable>
#include <iostream>
#include <set>
#include <thread>
#include <utility>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include "BackfillPubSubTypes.h"
#include "ChannelGrantPubSubTypes.h"
#include "ReceiverReportPubSubTypes.h"
#include "base/config_error.hpp"
#include "base/dds_security.hpp"
#include "core/wire_model.hpp"
#include "gateway/dds/coalescing_transport.hpp"
#include "gateway/dds/introduction_schedule.hpp"
#include "passthrough/dds_time.hpp"
#include "passthrough/guarded_type.hpp"
#include "passthrough/passthrough_qos.hpp"
#include "passthrough/passthrough_type.hpp"
#include "passthrough/type_object_guard.hpp"
#include "wire/backfill_topics.hpp"
#include "wire/channel_grant_topic.hpp"
#include "wire/receiver_report_topic.hpp"

namespace tgw::dds {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastdds::rtps::UDPv4TransportDescriptor;
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;
using eprosima::fastrtps::types::ReturnCode_t;

/// Announces the WAN participant again to participants that discovered it not (IntroductionSchedule), from a
/// thread of its own: Fast DDS's listener callbacks must not call back into the participant.
class WanRouter::Introducer {
  public:
    ~Introducer() { stop(); }

    void discovered(const IntroductionSchedule::Prefix& participant) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            schedule_.discovered(participant, base::SteadyClock::now());
        }
        wake_.notify_one();
    }
    void answered(const IntroductionSchedule::Prefix& participant) {
        std::lock_guard<std::mutex> lock(mutex_);
        schedule_.answered(participant);
    }
    void removed(const IntroductionSchedule::Prefix& participant) {
        std::lock_guard<std::mutex> lock(mutex_);
        schedule_.removed(participant);
    }
    /// Once, as soon as the thread can: the link is back, and what was announced while it was down was lost.
    void announce_now() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            announce_now_ = true;
        }
        wake_.notify_one();
    }

    /// Starts announcing through `participant`, which must outlive stop(); again after stop(), for a new one.
    void start(fdds::DomainParticipant* participant) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = false;
            schedule_ = IntroductionSchedule();
        }
        participant_ = participant;
        user_data_ = participant->get_qos().user_data().data_vec();
        thread_ = std::thread([this] { run(); });
    }
    void stop() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
        }
        wake_.notify_one();
        if (thread_.joinable()) {
            thread_.join();
        }
    }

    std::uint64_t announcements() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return announcements_;
    }

  private:
    void run() {
        std::unique_lock<std::mutex> lock(mutex_);
        while (!stopping_) {
            if (!announce_now_) {
                const std::optional<base::SteadyTime> next = schedule_.next_due();
                if (!next) {
                    wake_.wait(lock);
                    continue;
                }
                wake_.wait_until(lock, *next);
                if (stopping_ || (!announce_now_ && !schedule_.take_due(base::SteadyClock::now()))) {
                    continue;
                }
            }
            announce_now_ = false;
            ++announcements_;
            const std::uint64_t count = announcements_;
            lock.unlock();
            announce(count);
            lock.lock();
        }
    }

    /// Fast DDS 2.9 offers no call that sends the participant's announcement, but sends it at once to every peer
    /// when the participant's user data changes: a byte after the participant's own counts the introductions.
    void announce(std::uint64_t count) {
        fdds::DomainParticipantQos qos = participant_->get_qos();
        std::vector<eprosima::fastrtps::rtps::octet> data = user_data_;
        data.push_back(static_cast<eprosima::fastrtps::rtps::octet>(count));
        qos.user_data().data_vec(data);
        if (participant_->set_qos(qos) != ReturnCode_t::RETCODE_OK) {
            std::cerr << "telemetry-gateway: cannot announce the WAN participant again\n";
        }
    }

    fdds::DomainParticipant* participant_ = nullptr;
    std::vector<eprosima::fastrtps::rtps::octet> user_data_;  ///< the participant's own, from its QoS
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    IntroductionSchedule schedule_;    // under mutex_
    bool stopping_ = false;            // under mutex_
    bool announce_now_ = false;        // under mutex_
    std::uint64_t announcements_ = 0;  // under mutex_
    std::thread thread_;
};

/// Counts the base-camp participants the WAN participant has discovered: each new endpoint's SEDP announcement
/// goes to each of them. With DDS Security, those it has authenticated: Fast DDS reports a participant discovered
/// from its first announcement, before the handshake, and one that fails it (another CA's) never gets an SEDP.
class WanRouter::ParticipantCounter final : public passthrough::TypeObjectGuard {
  public:
    ParticipantCounter(bool secured, Introducer& introducer,
                       std::function<void(passthrough::DiscoveredPublisher&&)> on_remote_publisher)
        : secured_(secured), introducer_(introducer), on_remote_publisher_(std::move(on_remote_publisher)) {}

    void on_participant_discovery(fdds::DomainParticipant* /*participant*/,
                                  eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override {
        using Status = eprosima::fastrtps::rtps::ParticipantDiscoveryInfo;
        const auto& prefix = info.info.m_guid.guidPrefix;
        std::lock_guard<std::mutex> lock(mutex_);
        if (info.status == Status::DISCOVERED_PARTICIPANT) {
            discovered_.insert(prefix);
            introducer_.discovered(to_array(prefix));
        } else if (info.status == Status::REMOVED_PARTICIPANT || info.status == Status::DROPPED_PARTICIPANT) {
            discovered_.erase(prefix);
            authenticated_.erase(prefix);
            introducer_.removed(to_array(prefix));
        }
    }

    // A participant announces its endpoints to those it has discovered only: one announced to us knows us.
    void on_publisher_discovery(fdds::DomainParticipant* participant,
                                eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override {
        std::shared_ptr<const eprosima::fastrtps::types::TypeObject> type_object =
            passthrough::take_type_object(participant, info.info);
        if (info.status != eprosima::fastrtps::rtps::WriterDiscoveryInfo::DISCOVERED_WRITER) {
            return;
        }
        const auto& prefix = info.info.guid().guidPrefix;
        introducer_.answered(to_array(prefix));
        // Its own writers are reported too.
        if (on_remote_publisher_ && participant != nullptr && prefix != participant->guid().guidPrefix) {
            on_remote_publisher_(passthrough::discovered_publisher(info.info, std::move(type_object)));
        }
    }
    void on_subscriber_discovery(fdds::DomainParticipant* participant,
                                 eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) override {
        if (info.status == eprosima::fastrtps::rtps::ReaderDiscoveryInfo::DISCOVERED_READER) {
            introducer_.answered(to_array(info.info.guid().guidPrefix));
        }
        passthrough::TypeObjectGuard::on_subscriber_discovery(participant, std::move(info));
    }

#if HAVE_SECURITY
    void onParticipantAuthentication(fdds::DomainParticipant* /*participant*/,
                                     eprosima::fastrtps::rtps::ParticipantAuthenticationInfo&& info) override {
        using Status = eprosima::fastrtps::rtps::ParticipantAuthenticationInfo;
        std::lock_guard<std::mutex> lock(mutex_);
        if (info.status == Status::AUTHORIZED_PARTICIPANT) {
            authenticated_.insert(info.guid.guidPrefix);
        } else {
            authenticated_.erase(info.guid.guidPrefix);
        }
    }
#endif

    /// The participant these were discovered by is gone.
    void forget_all() {
        std::lock_guard<std::mutex> lock(mutex_);
        discovered_.clear();
        authenticated_.clear();
    }

    std::size_t count() const {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!secured_) {
            return discovered_.size();
        }
        // Authenticated and not yet removed.
        return static_cast<std::size_t>(std::count_if(authenticated_.begin(), authenticated_.end(),
                                                      [this](const auto& p) { return discovered_.count(p) != 0; }));
    }

  private:
    static IntroductionSchedule::Prefix to_array(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix) {
        IntroductionSchedule::Prefix out;
        std::copy(std::begin(prefix.value), std::end(prefix.value), out.begin());
        return out;
    }

    const bool secured_;
    Introducer& introducer_;
    const std::function<void(passthrough::DiscoveredPublisher&&)> on_remote_publisher_;
    mutable std::mutex mutex_;
    std::set<eprosima::fastrtps::rtps::GuidPrefix_t> discovered_;     // under mutex_
    std::set<eprosima::fastrtps::rtps::GuidPrefix_t> authenticated_;  // under mutex_
};

namespace {

/// Participant ids of one host on one domain, in practice; RTPS's port arithmetic runs into the next domain's ports
/// from 120 on.
constexpr std::uint32_t MAX_PINNED_PARTICIPANT_ID = 120;

Locator_t udp_locator(const std::string& address, std::uint16_t port) {
    Locator_t locator;
    locator.kind = LOCATOR_KIND_UDPv4;
    if (!address.empty()) {
        IPLocator::setIPv4(locator, address);
    }
    locator.port = port;
    return locator;
}

}  // namespace

WanRouter::WanRouter(const WanConfig& config, const std::optional<fdds::DomainParticipantQos>& base)
    : coalescer_(std::make_shared<DatagramCoalescer>(config.coalesce_window, config.max_datagram_bytes, clock_,
                                                     HeldControl{config.control_wait, config.on_unscheduled})),
      domain_(config.domain),
      listen_port_(config.listen_port),
      introducer_(std::make_unique<Introducer>()),
      participants_(
          std::make_unique<ParticipantCounter>(config.security.has_value(), *introducer_, config.on_remote_publisher)) {
    fdds::DomainParticipantQos& qos = qos_;
    qos = base ? *base : fdds::DomainParticipantFactory::get_instance()->get_default_participant_qos();
    qos.name("telemetry-gateway/wan");

    // UDPv4 only: no shared memory (the base camp is elsewhere), bound to the WAN interface.
    qos.transport().use_builtin_transports = false;
    qos.transport().user_transports.clear();
    std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface> udp = config.datagram_transport;
    if (!udp) {
        udp = std::make_shared<UDPv4TransportDescriptor>();
    }
    // By default one RTPS message per Ethernet frame: larger samples go as DATA_FRAG, which the wire model
    // counts and a reliable writer can repair one by one, instead of IP fragments of one 64 kB datagram.
    udp->maxMessageSize = static_cast<std::uint32_t>(config.max_datagram_bytes);
    // No interface whitelist: Fast DDS filters it against the interfaces that are up when the participant is
    // made, once, so a gateway started before its radio kept no interface for its life (192.0.2.0, "All whitelist
    // interfaces were filtered out"). The locators below bind what it listens on and announces to the interface's
    // address, which stays assigned while the link is down; it sends from a socket on every address, and the
    // routing table takes the datagrams to the radio once it is up.
    auto coalescing =
        std::make_shared<CoalescingTransportDescriptor>(udp, coalescer_, config.on_unscheduled, repeat_throttle_);
    coalescing->heartbeat_spacing_bytes = config.heartbeat_spacing_bytes;
    coalescing->strip_statistics = config.strip_statistics;
    coalescing->strip_statistics_without_samples = config.strip_statistics_without_samples;
    coalescing->strip_destination = config.strip_destination;
    coalescing->strip_timestamp = config.strip_timestamp;
    coalescing->strip_early_heartbeats = config.strip_early_heartbeats;
    coalescing->first_output_socket_only = true;  // no whitelist, no multicast
    if (config.schedule_repairs || config.schedule_announcements) {
        repair_desk_ = std::make_shared<RepairDesk>(coalescer_, clock_, config.schedule_repairs);
        coalescing->repair_desk = repair_desk_;
    }
    qos.transport().user_transports.push_back(coalescing);

    auto& builtin = qos.wire_protocol().builtin;
    builtin.metatrafficMulticastLocatorList.clear();
    qos.wire_protocol().default_multicast_locator_list.clear();
    peers_ = config.peers;
    if (config.discovery_server) {
        // The gateway reads the receiver reports and, with --uplink, the commands (WanConfig::discovery_role).
        base::apply_discovery_client(qos, *config.discovery_server, config.discovery_role);
    }
    if (!base) {
        // A participant profile from the --qos file sets its own discovery timing.
        builtin.discovery_config.leaseDuration = passthrough::to_dds_duration(config.lease_duration);
        builtin.discovery_config.leaseDuration_announcementperiod =
            passthrough::to_dds_duration(config.announcement_period);
    }

    if (config.security) {
        // On top of a participant profile too: the flag's identity is the one to use.
        base::apply_dds_security(qos, *config.security);
    }

    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!create_participant_nts(config.interface_address)) {
            throw base::ConfigError("--wan-domain " + std::to_string(config.domain) +
                                    ": cannot create the WAN participant (check --wan-interface and --wan-peer" +
                                    (config.security ? ", and Fast DDS's log about --wan-security" : "") + ")");
        }
    }
    coalescer_->start();
    introducer_->start(participant_);
}

bool WanRouter::create_participant_nts(const std::string& interface_address) {
    fdds::DomainParticipantQos qos = qos_;
    // An explicit metatraffic unicast locator and no multicast one: Fast DDS then opens no multicast
    // listener and announces only to the initial peers. Port 0 means the participant id's well-known port.
    auto& builtin = qos.wire_protocol().builtin;
    builtin.metatrafficUnicastLocatorList.clear();
    builtin.metatrafficUnicastLocatorList.push_back(udp_locator(interface_address, listen_port_));
    builtin.initialPeersList.clear();
    for (const base::WanPeer& peer : peers_) {
        builtin.initialPeersList.push_back(udp_locator(peer.address, peer.port));
    }
    if (!interface_address.empty()) {
        // Its readers (the receiver reports, the commands) announce the interface's address alone, not every
        // address of the robot.
        qos.wire_protocol().default_unicast_locator_list.clear();
        qos.wire_protocol().default_unicast_locator_list.push_back(udp_locator(interface_address, 0));
    }
    const fdds::StatusMask discovery_only = fdds::StatusMask::none();
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    participant_ =
        factory->create_participant(static_cast<fdds::DomainId_t>(domain_), qos, participants_.get(), discovery_only);
    if (participant_ == nullptr) {
        return false;
    }
    publishers_ = passthrough::PartitionGroups<fdds::Publisher>();
    publisher_ = publishers_.get(participant_, passthrough::OfferedQos{});
    if (publisher_ == nullptr) {
        factory->delete_participant(participant_);
        participant_ = nullptr;
        return false;
    }
    interface_address_ = interface_address;
    if (listen_port_ == 0) {
        // Made anew (another address), the participant keeps the port it announced from the start: Fast DDS would
        // give it the next participant id's, and a camp that knows the robot by its address alone announces to
        // participant 0's (and the quiet discovery ports would hold that one). Fast DDS's GUID prefix ends with
        // the participant id, little-endian (its GuidUtils); DDS Security rewrites the prefix from the identity, and
        // an id out of range is taken for that: Fast DDS's choice then stands.
        const auto& prefix = participant_->guid().guidPrefix.value;
        const std::uint32_t id = static_cast<std::uint32_t>(prefix[8]) | static_cast<std::uint32_t>(prefix[9]) << 8 |
                                 static_cast<std::uint32_t>(prefix[10]) << 16 |
                                 static_cast<std::uint32_t>(prefix[11]) << 24;
        if (id < MAX_PINNED_PARTICIPANT_ID) {
            listen_port_ = base::metatraffic_unicast_port(domain_, static_cast<int>(id));
        }
    }
    return true;
}

void WanRouter::delete_participant_nts() {
    if (participant_ == nullptr) {
        return;
    }
    participant_->set_listener(nullptr);
    participant_->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
    participant_ = nullptr;
    publisher_ = nullptr;
    live_writers_.clear();
    writers_of_topic_.clear();
}

bool WanRouter::rebind(const std::string& interface_address) {
    return rebind(interface_address, peers());
}

std::vector<base::WanPeer> WanRouter::peers() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return peers_;
}

bool WanRouter::rebind(const std::string& interface_address, const std::vector<base::WanPeer>& peers) {
    introducer_->stop();
    // Held until the lock is released: a WanWriter whose last holder lets go here deletes its writer through
    // delete_writer(), which takes the lock.
    std::vector<std::shared_ptr<WanWriter>> kept;
    bool made = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const WriterRecipe& recipe : recipes_) {
            if (auto writer = recipe.writer.lock()) {
                writer->detach();  // waits for a write in progress
                kept.push_back(std::move(writer));
            }
        }
        // The transport's destructor sends what the coalescer keeps for it and drops the repairs held for it.
        delete_participant_nts();
        participants_->forget_all();
        peers_ = peers;
        made = create_participant_nts(interface_address);
        if (made) {
            std::vector<WriterRecipe> alive;
            for (WriterRecipe& recipe : recipes_) {
                const auto writer = recipe.writer.lock();
                if (!writer) {
                    continue;
                }
                if (fdds::DataWriter* successor = create_datawriter_nts(recipe, writer->match_listener())) {
                    writer->replace(successor);
                }
                alive.push_back(std::move(recipe));
            }
            recipes_ = std::move(alive);
        }
    }
    kept.clear();
    if (!made) {
        std::cerr << "telemetry-gateway: cannot make the WAN participant anew on " << interface_address
                  << "; nothing is sent until it can be\n";
        return false;
    }
    for (const auto& subscribe : subscriptions_) {
        subscribe();
    }
    introducer_->start(participant_);
    introducer_->announce_now();
    return true;
}

std::string WanRouter::interface_address() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return interface_address_;
}

WanRouter::~WanRouter() {
    introducer_->stop();
    if (repair_desk_) {
        repair_desk_->stop();  // what it holds refers to the transport's channels
    }
    // Sends what waits while the transport's channels still exist.
    coalescer_->stop();
    std::lock_guard<std::mutex> lock(mutex_);
    delete_participant_nts();
}

std::optional<fdds::DataWriterQos> WanRouter::writer_profile(const std::string& topic) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return writer_profile_nts(topic);
}

std::optional<fdds::DataWriterQos> WanRouter::writer_profile_nts(const std::string& topic) const {
    fdds::DataWriterQos qos;
    if (publisher_ == nullptr || publisher_->get_datawriter_qos_from_profile(topic, qos) != ReturnCode_t::RETCODE_OK) {
        return std::nullopt;
    }
    return qos;
}

std::shared_ptr<WanWriter> WanRouter::create_writer(
    const std::string& topic, const std::string& wan_topic, const std::string& type_name, bool keyed,
    std::optional<base::Duration> lifespan, const passthrough::OfferedQos& offer,
    const std::shared_ptr<const eprosima::fastrtps::types::TypeObject>& announced) {
    auto matches = std::make_unique<passthrough::WriterMatchCounter>();
    WriterRecipe recipe{{}, topic, wan_topic, type_name, keyed, lifespan, offer, announced};

    std::lock_guard<std::mutex> lock(mutex_);
    fdds::DataWriter* writer = create_datawriter_nts(recipe, matches.get());
    if (writer == nullptr) {
        return nullptr;
    }
    auto made = std::make_shared<WanWriter>(writer, std::move(matches), wan_topic, keyed,
                                            [this](fdds::DataWriter* w) { delete_writer(w); });
    recipe.writer = made;
    recipes_.push_back(std::move(recipe));
    return made;
}

fdds::DataWriter* WanRouter::create_datawriter_nts(const WriterRecipe& recipe, fdds::DataWriterListener* listener) {
    if (participant_ == nullptr) {
        return nullptr;
    }
    fdds::Topic* dds_topic = passthrough::passthrough_topic(participant_, recipe.wan_topic, recipe.type_name,
                                                            recipe.keyed, recipe.announced);
    fdds::Publisher* publisher = publishers_.get(participant_, recipe.offer);
    if (dds_topic == nullptr || publisher == nullptr) {
        std::cerr << "telemetry-gateway: cannot create WAN topic " << recipe.wan_topic << " (type " << recipe.type_name
                  << ")\n";
        drop_unused_topic_nts(dds_topic);
        return nullptr;
    }

    // A data_writer profile named after the topic is the starting point (its Lifespan already made the TTL);
    // what decides matching is the publishers' offer, except that a profile may ask for best effort.
    const std::optional<fdds::DataWriterQos> profile = writer_profile_nts(recipe.topic);
    fdds::DataWriterQos qos = passthrough::passthrough_writer_qos(
        profile.value_or(publisher->get_default_datawriter_qos()), recipe.offer, recipe.keyed, recipe.lifespan);
    if (profile && profile->reliability().kind == fdds::BEST_EFFORT_RELIABILITY_QOS) {
        // The operator's word (a writer's default is reliable, so this was asked for): no HEARTBEAT or
        // ACKNACK on the link for this topic, at the price of reliable base-camp readers not matching.
        qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
    }

    fdds::DataWriter* writer = publisher->create_datawriter(dds_topic, qos, listener, fdds::StatusMask::all());
    if (writer == nullptr) {
        std::cerr << "telemetry-gateway: cannot create the WAN writer for " << recipe.wan_topic << " ("
                  << recipe.offer.describe() << ")\n";
        drop_unused_topic_nts(dds_topic);
        return nullptr;
    }
    ++writers_of_topic_[recipe.wan_topic];
    live_writers_.insert(writer);
    return writer;
}

void WanRouter::delete_writer(fdds::DataWriter* writer) {
    std::lock_guard<std::mutex> lock(mutex_);
    recipes_.erase(std::remove_if(recipes_.begin(), recipes_.end(),
                                  [](const WriterRecipe& recipe) { return recipe.writer.expired(); }),
                   recipes_.end());
    if (live_writers_.erase(writer) == 0) {
        return;  // it went with a participant made anew since
    }
    fdds::Topic* topic = writer->get_topic();
    const_cast<fdds::Publisher*>(writer->get_publisher())->delete_datawriter(writer);
    const auto it = writers_of_topic_.find(topic->get_name());
    if (it != writers_of_topic_.end() && --it->second == 0) {
        writers_of_topic_.erase(it);
        participant_->delete_topic(topic);
    }
}

void WanRouter::drop_unused_topic_nts(fdds::Topic* topic) {
    if (topic != nullptr && writers_of_topic_.count(topic->get_name()) == 0) {
        participant_->delete_topic(topic);
    }
}

std::size_t WanRouter::topic_count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return writers_of_topic_.size();
}

std::size_t WanRouter::remote_participants() const {
    return participants_->count();
}

std::uint64_t WanRouter::introductions() const {
    return introducer_->announcements();
}

void WanRouter::announce_again() {
    introducer_->announce_now();
}

bool WanRouter::subscribe_receiver_reports(fdds::DataReaderListener* listener) {
    subscriptions_.push_back([this, listener] {
        return subscribe(wire::RECEIVER_REPORT_TOPIC,
                         fdds::TypeSupport(new passthrough::GuardedType<idl::ReceiverReportPubSubType>()), listener);
    });
    return subscriptions_.back()();
}

bool WanRouter::subscribe_grants(fdds::DataReaderListener* listener) {
    subscriptions_.push_back([this, listener] {
        return subscribe(wire::CHANNEL_GRANT_TOPIC,
                         fdds::TypeSupport(new passthrough::GuardedType<idl::ChannelGrantPubSubType>()), listener);
    });
    return subscriptions_.back()();
}

bool WanRouter::subscribe_backfill_acks(fdds::DataReaderListener* listener) {
    // Each acknowledgement tells only what is new since the last: a few kept per log, so that none is replaced
    // before it is taken.
    constexpr std::int32_t KEPT = 16;
    subscriptions_.push_back([this, listener] {
        return subscribe(wire::BACKFILL_ACK_TOPIC,
                         fdds::TypeSupport(new passthrough::GuardedType<idl::BackfillAckPubSubType>()), listener, KEPT);
    });
    return subscriptions_.back()();
}

bool WanRouter::subscribe(const char* topic_name, fdds::TypeSupport type, fdds::DataReaderListener* listener,
                          std::int32_t reliable_depth) {
    if (participant_ == nullptr) {
        return false;
    }
    if (participant_->register_type(type) != ReturnCode_t::RETCODE_OK) {
        std::cerr << "telemetry-gateway: cannot register the type of " << topic_name << '\n';
        return false;
    }
    fdds::Topic* topic = participant_->create_topic(topic_name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    fdds::Subscriber* subscriber = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    if (topic == nullptr || subscriber == nullptr) {
        std::cerr << "telemetry-gateway: cannot subscribe to " << topic_name << '\n';
        return false;
    }
    fdds::DataReaderQos qos = subscriber->get_default_datareader_qos();
    // Best effort and the latest per sender where every sample carries all it has to say.
    qos.reliability().kind = reliable_depth > 0 ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
    qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
    qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    qos.history().depth = std::max<std::int32_t>(1, reliable_depth);
    qos.data_sharing().off();
    qos.expects_inline_qos(false);
    if (subscriber->create_datareader(topic, qos, listener) == nullptr) {
        std::cerr << "telemetry-gateway: cannot create the reader of " << topic_name << '\n';
        return false;
    }
    return true;
}

eprosima::fastrtps::rtps::GuidPrefix_t WanRouter::guid_prefix() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return participant_ != nullptr ? participant_->guid().guidPrefix : eprosima::fastrtps::rtps::GuidPrefix_t();
}

}  // namespace tgw::dds
