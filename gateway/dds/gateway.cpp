#include "gateway/dds/gateway.hpp"

#include <algorithm>
#include <iostream>
#include <utility>

#include "BackfillPubSubTypes.h"
#include "GatewayStatusPubSubTypes.h"
#include "base/config_error.hpp"
#include "base/wan_address.hpp"
#include "gateway/dds/compact_wan.hpp"
#include "gateway/dds/gateway_sink.hpp"
#include "gateway/dds/robot_participant.hpp"
#include "gateway/dds/status_publisher.hpp"
#include "gateway/dds/topic_table.hpp"
#include "gateway/dds/wan_router.hpp"
#include "gateway/dds/wan_setup.hpp"
#include "gateway/log/robot_log.hpp"
#include "passthrough/qos_file.hpp"
#include "wire/backfill_topics.hpp"
#include "wire/receiver_report_topic.hpp"
#include "wire/status_topic.hpp"

namespace tgw::dds {

namespace {

// How often the worker looks whether base-camp readers matched or left. A topic nobody reads keeps its samples
// queued (Scheduler::set_reachable); they start to flow within this of a reader matching.
constexpr auto REACHABILITY_POLL = std::chrono::milliseconds(100);

}  // namespace

struct Gateway::WanCallbackLink {
    std::mutex mutex;
    Gateway* gateway = nullptr;  ///< null once the Gateway is being destroyed
};

Gateway::Gateway(GatewayConfig config, const base::Clock& clock)
    : config_(std::move(config)),
      clock_(clock),
      filter_(config_.allow, config_.deny, config_.topic_rules),
      types_(types::TypeLibrary::project_and(config_.idl_dirs, "--idl")),
      wan_callbacks_(std::make_shared<WanCallbackLink>()),
      uplink_topics_(config_.uplink, config_.robot_name) {
    config_.validate();
    // The identity first: a missing or tampered file stops the start before anything is created.
    std::optional<base::SecurityFiles> security;
    if (!config_.wan_security.empty()) {
        security = base::SecurityFiles::load(config_.wan_security, "--wan-security");
    }
    wan_callbacks_->gateway = this;
    if (!config_.log_file.empty()) {
        log_ = std::make_unique<log::RobotLog>(config_.log_file, config_.log_max_bytes);
    }
    if (!config_.qos_file.empty()) {
        passthrough::load_qos_file(config_.qos_file);
    }

    peer_specs_ = wan_peers_of(config_);
    // The camp's datagrams (its commands) come as its Fast DDS sends them, whatever this end strips from its own.
    camp_wire_ = security ? config_.scheduler.wire.with_security() : config_.scheduler.wire;
    WanConfig wan = wan_config_for(config_, std::move(security), peer_specs_);
    // Discovery, heartbeats, repairs, copies to further readers: charged as they leave, so that the budget
    // counts every byte the WAN participant puts on the link (docs/design.md §3).
    wan.on_unscheduled = [link = wan_callbacks_](std::uint64_t frame_bytes) {
        std::lock_guard<std::mutex> lock(link->mutex);
        if (link->gateway != nullptr) {
            link->gateway->charge_unscheduled(frame_bytes);
        }
    };
    if (!uplink_topics_.empty()) {
        wan.on_remote_publisher = [link = wan_callbacks_](passthrough::DiscoveredPublisher&& pub) {
            std::lock_guard<std::mutex> lock(link->mutex);
            if (link->gateway != nullptr) {
                link->gateway->remote_publisher_discovered(std::move(pub));
            }
        };
        wan.discovery_role = base::DiscoveryRole::super_client;
    }
    wan_ = std::make_unique<WanRouter>(wan, passthrough::participant_profile(passthrough::WAN_PARTICIPANT_PROFILE));
    if (base::QuietDiscoveryPorts::worth_it(wan.interface_address)) {
        // Once the WAN participant has its own port: a base camp announcing itself to the others (Cyclone's
        // peers by address) draws no ICMP from this host over the radio.
        quiet_ports_ = base::QuietDiscoveryPorts(wan.interface_address, config_.wan_domain);
    }

    if (config_.compact_wan) {
        compact_ = std::make_unique<CompactWan>(
            *wan_, config_.scheduler.wire,
            config_.wan_compress ? compact::BundleCompression::zstd_if_smaller : compact::BundleCompression::none);
        if (!config_.scheduler.bundles) {
            config_.scheduler.bundles = core::BundleLimits{core::BundleLimits::one_datagram(config_.scheduler.wire)};
        }
    }

    topics_ = std::make_unique<TopicTable>();
    sink_ = std::make_unique<GatewaySink>(*topics_, log_.get(), clock_);
    sink_->set_compact(compact_.get());
    sink_->set_repair_desk(wan_->repair_desk());
    loop_ = std::make_unique<core::ForwardingLoop>(config_.scheduler, clock_, *sink_);
    charging_loop_.store(loop_.get());
    rate_ = std::make_unique<RateControl>(*loop_, *wan_, log_.get(), config_.scheduler.budget_fraction,
                                          config_.scheduler.initial_rate_bps, clock_);
    lifecycle_ = std::make_unique<TopicLifecycle>(
        config_, filter_, types_, TopicLifecycle::Ends{*wan_, *loop_, *topics_, worker_, clock_, compact_.get()});
    if (RepairDesk* desk = wan_->repair_desk()) {
        desk->set_submit([loop = loop_.get()](const core::Repair& repair) { loop->submit_repair(repair); });
        desk->pace_fragments(core::paces_fragments_at(config_.scheduler.initial_rate_bps));
        desk->set_topic_lookup([lifecycle = lifecycle_.get()](std::string_view wan_topic) {
            return lifecycle->scheduled_topic(wan_topic);
        });
    }
    if (config_.status_period > base::Duration::zero()) {
        // The status is scheduled like a sample of a topic with a TTL of STATUS_TTL, so its bytes leave only when
        // the budget has room for them. Under grants it goes first, and its deadline is its Lifespan: a robot
        // granted its least share sends a status within about a second, but behind a sample already on the wire
        // it could not within STATUS_TTL, and a status doomed each time never told the base camp of the demand
        // that would raise the grant. Within that Lifespan it yields to a sample it would make late.
        passthrough::OfferedQos offer;
        offer.reliable = true;  // matched by any reader's defaults
        status_topic_ = loop_->add_topic(
            core::TopicConfig{wire::STATUS_TOPIC, config_.channel_grants ? wire::STATUS_LIFESPAN : wire::STATUS_TTL,
                              config_.channel_grants, wire::STATUS_LIFESPAN});
        if (compact_) {
            compact_->announce(CatalogLane{*status_topic_, wire::STATUS_TOPIC, idl::GatewayStatusPubSubType().getName(),
                                           true, wire::STATUS_TTL, 0, offer, wire::STATUS_LIFESPAN, true});
        } else {
            status_writer_ =
                wan_->create_writer(wire::STATUS_TOPIC, wire::STATUS_TOPIC, idl::GatewayStatusPubSubType().getName(),
                                    true, wire::STATUS_LIFESPAN, offer, nullptr);
            if (status_writer_ == nullptr) {
                throw base::ConfigError("--status-period: cannot create the writer of " +
                                        std::string(wire::STATUS_TOPIC));
            }
        }
        sink_->set_status_route(*status_topic_, status_writer_);
        StatusPublisher::Config status{config_.status_period,  config_.robot_name,
                                       config_.compact_wan,    config_.channel_grants,
                                       config_.scheduler.wire, config_.scheduler.budget_fraction};
        status_ = std::make_unique<StatusPublisher>(
            status, *loop_, *status_topic_, clock_,
            StatusPublisher::Sources{[this] { return status_rows(); },
                                     [this](idl::GatewayStatus& s, std::int32_t readers) { fill_status(s, readers); },
                                     [this](double least_share_bps) { rate_->set_least_share(least_share_bps); }});
    }
    if (config_.backfill) {
        start_backfill();
    }
    loop_->start();
    if (config_.receiver_reports) {
        // After the loop: each report is compared with what the loop had forwarded when it came.
        reports_ = std::make_unique<ReceiverReportReader>(
            wan_->guid_prefix(), [this] { return forwarded_robot_samples(); }, clock_);
        if (!wan_->subscribe_receiver_reports(reports_.get())) {
            throw base::ConfigError("--receiver-reports: cannot subscribe to the base camp's reports");
        }
    }
    // Until the sensor's first reading: what a grant, or the WAN link coming up, applies again.
    if (config_.channel_grants) {
        // A grant applies as it comes; the sensor's next reading applies it again, or without it once it ran out.
        grants_ = std::make_unique<GrantReader>(wan_->guid_prefix(), clock_, [this] { rate_->apply(); });
        rate_->set_grants(grants_.get());
        if (!wan_->subscribe_grants(grants_.get())) {
            throw base::ConfigError("--channel-grants: cannot subscribe to the base camp's grants");
        }
    }

    discovery_ = std::make_unique<passthrough::Discovery>(
        [this](passthrough::DiscoveredPublisher&& pub) {
            worker_.post([this, pub = std::move(pub)]() mutable { lifecycle_->gather_nts(std::move(pub)); });
        },
        [this](const std::string& topic, const eprosima::fastrtps::rtps::GUID_t& writer) {
            worker_.post([this, topic, writer] { lifecycle_->forget_writer_nts(topic, writer); });
        });
    discovery_->ignore_participant(wan_->guid_prefix());
    worker_.post([this] { poll_reachability_nts(); });
    if (config_.status_period > base::Duration::zero()) {
        // The first after one period: by then the sensor has been described and read.
        worker_.post_at(std::chrono::steady_clock::now() +
                            std::chrono::duration_cast<std::chrono::steady_clock::duration>(config_.status_period),
                        [this] { publish_status_nts(); });
    }
    try {
        RobotTransport transport = config_.robot;
        for (std::string& interface : transport.interfaces) {
            interface = base::resolve_interface_address(interface, "--robot-interface");
        }
        // The declared topics go to the worker first, before any publisher the robot participant finds: a lane
        // declared after a running publisher had its own would not carry it (TopicBridge::lane_for_nts), and the
        // publisher's samples would cross with its QoS instead of the file's.
        if (!config_.qos_file.empty()) {
            for (const passthrough::DeclaredTopic& declared : passthrough::declared_topics(config_.qos_file)) {
                passthrough::DiscoveredPublisher pub;
                pub.topic = declared.topic;
                pub.type_name = declared.type_name;
                pub.keyed = declared.keyed;
                pub.lifespan = declared.lifespan;
                pub.qos = passthrough::OfferedQos::from_writer(declared.qos, declared.keyed);
                worker_.post([this, pub = std::move(pub)] { lifecycle_->bridge_nts(pub, true); });
            }
        }
        // Discovery starts inside the participant's creation, and what it finds is posted to the worker: the
        // worker starts once robot_ is set, so that nothing found meanwhile meets a participant not yet there.
        robot_ = std::make_unique<RobotParticipant>(
            config_.robot_domain, discovery_.get(), transport,
            passthrough::participant_profile(passthrough::ROBOT_PARTICIPANT_PROFILE));
        discovery_->ignore_participant(robot_->guid_prefix());
        lifecycle_->set_robot(*robot_);
        make_uplink();
        worker_.start();
        if (std::any_of(peer_specs_.begin(), peer_specs_.end(),
                        [](const base::WanPeer& p) { return !p.host.empty(); })) {
            peer_lookup_ = std::make_unique<PeerLookup>(peer_specs_, [this](const std::vector<base::WanPeer>& now) {
                const std::vector<base::WanPeer> peers =
                    base::announcement_peers(now, config_.wan_domain, config_.wan_peer_participants);
                post_wan_remake([this, peers] { remake_wan_nts(wan_->interface_address(), peers); });
            });
        }
    } catch (...) {
        stop();
        throw;
    }
}

Gateway::~Gateway() {
    stop();
    // The WAN participant outlives the members its transport's callback would use.
    std::lock_guard<std::mutex> lock(wan_callbacks_->mutex);
    wan_callbacks_->gateway = nullptr;
}

void Gateway::stop() {
    std::lock_guard<std::mutex> lock(stop_mutex_);
    if (stopped_) {
        return;
    }
    stopped_ = true;
    if (peer_lookup_) {
        peer_lookup_->stop();
    }
    if (reports_) {
        // Reports keep coming until the WAN participant goes, after the loop and the topics they are counted
        // against.
        reports_->close();
    }
    if (grants_) {
        grants_->close();  // likewise: a grant sets the loop's rate
    }
    if (backfill_acks_) {
        backfill_acks_->close();
    }
    worker_.stop();
    if (robot_) {
        for (const std::shared_ptr<TopicBridge>& bridge : topics_->all()) {
            bridge->close_readers();
        }
    }
    if (uplink_) {
        uplink_->close();  // its writers are the robot participant's
    }
    robot_.reset();
    if (RepairDesk* desk = wan_->repair_desk()) {
        desk->stop();  // before the loop: nothing more is submitted to it
    }
    loop_->stop();
    if (backfill_) {
        backfill_->stop();  // after the loop, which asks it for samples until it stops
    }
    if (log_) {
        log_->flush();
    }
}

void Gateway::start_backfill() {
    // The least urgent topic of all: its samples go only when no live sample wants the link (core::IdleSource),
    // and wait behind any that comes. Best effort: the camp's acknowledgements make it reliable, at the budget's
    // pace; a reliable writer's repairs would cross outside the schedule's order.
    backfill_topic_ = loop_->add_topic(core::TopicConfig{wire::BACKFILL_TOPIC, wire::BACKFILL_TTL});
    loop_->set_reachable(*backfill_topic_, false);  // until a camp that stores backfill reads it
    passthrough::OfferedQos offer;
    offer.reliable = false;
    // In compact mode its samples ride in bundles, and this writer writes nothing: its match says that a camp
    // archives backfill (a relay or a recorder with --out reads the topic), as in standard mode.
    backfill_writer_ =
        wan_->create_writer(wire::BACKFILL_TOPIC, wire::BACKFILL_TOPIC, idl::BackfillSamplePubSubType().getName(),
                            false, std::nullopt, offer, nullptr);
    if (backfill_writer_ == nullptr) {
        throw base::ConfigError("--backfill: cannot create the writer of " + std::string(wire::BACKFILL_TOPIC));
    }
    if (compact_) {
        compact_->announce(CatalogLane{*backfill_topic_, wire::BACKFILL_TOPIC,
                                       idl::BackfillSamplePubSubType().getName(), false, wire::BACKFILL_TTL, 0, offer,
                                       std::nullopt, false});
    }
    BackfillSender::Config backfill;
    backfill.planner.max_bps = config_.backfill_max_bps;
    backfill_ = std::make_unique<BackfillSender>(*log_, backfill, config_.scheduler.wire, clock_,
                                                 [loop = loop_.get()] { loop->kick(); });
    sink_->set_backfill_route(*backfill_topic_, backfill_writer_, backfill_.get());
    loop_->set_idle_source(backfill_.get(), *backfill_topic_);
    backfill_->start(*backfill_topic_);
    backfill_acks_ = std::make_unique<BackfillAckReader>(*backfill_);
    if (!wan_->subscribe_backfill_acks(backfill_acks_.get())) {
        throw base::ConfigError("--backfill: cannot subscribe to the base camp's acknowledgements");
    }
}

void Gateway::observe_link_backlog(std::uint64_t bytes) {
    loop_->observe_link_backlog(8u * bytes);
}

void Gateway::set_sensor_description(std::string description) {
    std::lock_guard<std::mutex> lock(sensor_mutex_);
    sensor_description_ = std::move(description);
}

void Gateway::apply_reading(const sensor::RateReading& reading) {
    {
        std::lock_guard<std::mutex> lock(sensor_mutex_);
        sensor_detail_ = reading.ok ? reading.detail : reading.error;
        if (reading.ok) {
            delivered_cap_bps_ = reading.cap_bps.value_or(0.0);
        }
    }
    if (!reading.ok) {
        return;  // the guarded sensor's failures never get here; a bare one keeps the last rate
    }
    set_rate(reading.rate_bps);
    if (reading.queued_bytes) {
        observe_link_backlog(*reading.queued_bytes);
    }
}

double Gateway::rate_bps() const {
    return loop_->rate_bps();
}

void Gateway::set_rate(double rate_bps) {
    rate_->sensed(rate_bps);
}

void Gateway::make_uplink() {
    if (uplink_topics_.empty()) {
        return;
    }
    passthrough::Uplink::Charge charge;
    if (config_.uplink_shares_link) {
        // Outside the schedule, as discovery is: so the status tells the base camp's grantor, and a robot's
        // grant leaves room for the commands the camp sends it on the shared channel.
        charge = [this](std::uint64_t frame_bytes) {
            rate_->commands_charged(frame_bytes);
            charge_unscheduled(frame_bytes);
        };
    }
    uplink_ = std::make_unique<passthrough::Uplink>(wan_->participant(), robot_->participant(), clock_, camp_wire_,
                                                    std::move(charge));
}

void Gateway::rebind_wan(const std::string& address) {
    post_wan_remake([this, address] { rebind_wan_nts(address); });
}

void Gateway::post_wan_remake(std::function<void()> remake) {
    // At once: a link that comes up with the new address must not be given a rate before the participant is
    // bound to it (what was written meanwhile would be counted forwarded and never arrive).
    rate_->set_rebinding(true);
    worker_.post(std::move(remake));
}

void Gateway::rebind_wan_nts(const std::string& address) {
    if (address.empty() || address == wan_->interface_address()) {
        rate_->set_rebinding(false);
        return;
    }
    remake_wan_nts(address, wan_->peers());
}

void Gateway::remake_wan_nts(const std::string& address, const std::vector<base::WanPeer>& peers) {
    if (uplink_) {
        uplink_->close();  // its readers are the old participant's
        uplink_.reset();
    }
    // Released first: the new participant must get its own well-known port, which they may hold on no address.
    quiet_ports_ = base::QuietDiscoveryPorts();
    if (wan_->rebind(address, peers)) {
        const auto prefix = wan_->guid_prefix();
        if (reports_) {
            reports_->set_own(prefix);
        }
        if (grants_) {
            grants_->set_own(prefix);
        }
        discovery_->ignore_participant(prefix);
        try {
            if (base::QuietDiscoveryPorts::worth_it(address)) {
                quiet_ports_ = base::QuietDiscoveryPorts(address, config_.wan_domain);
            }
        } catch (const base::ConfigError& error) {
            std::cerr << "telemetry-gateway: " << error.what() << '\n';
        }
        make_uplink();
        if (compact_) {
            compact_->announce_again();  // the catalog's writer starts with no history to give the camp
        }
        wan_rebinds_.fetch_add(1);
    }
    rate_->set_rebinding(false);
}

std::string Gateway::wan_interface_address() const {
    return wan_->interface_address();
}

void Gateway::set_wan_link_up(bool up) {
    const bool was_up = rate_->set_link_up(up);
    if (up && !was_up) {
        wan_->announce_again();
    }
}

std::optional<double> Gateway::granted_bps() const {
    return grants_ ? grants_->current() : std::nullopt;
}

void Gateway::poll_reachability_nts() {
    lifecycle_->poll_reachability_nts();
    if (status_topic_) {
        lifecycle_->set_reachable_nts(*status_topic_,
                                      (compact_ ? compact_->matched_readers() : status_writer_->matched_readers()) > 0);
    }
    if (backfill_topic_) {
        // A camp that stores backfill and acknowledges it reads the topic (tm-basecamp relay --out, record).
        lifecycle_->set_reachable_nts(*backfill_topic_, backfill_writer_->matched_readers() > 0);
    }
    worker_.post_at(std::chrono::steady_clock::now() + REACHABILITY_POLL, [this] { poll_reachability_nts(); });
}

void Gateway::remote_publisher_discovered(passthrough::DiscoveredPublisher&& pub) {
    std::optional<std::string> robot_topic = uplink_topics_.robot_topic(pub.topic);
    if (!robot_topic) {
        return;  // nothing else flows from the WAN into the robot domain
    }
    worker_.post(
        [this, pub = std::move(pub), robot_topic = std::move(*robot_topic)] { route_uplink_nts(pub, robot_topic); });
}

void Gateway::route_uplink_nts(const passthrough::DiscoveredPublisher& pub, const std::string& robot_topic) {
    if (!uplink_) {
        return;  // stopping
    }
    // The same rule as the robot's topics, by the robot's name of the topic.
    uplink_->route(pub, robot_topic, lifecycle_->ttl_for(robot_topic, pub.lifespan));
}

std::vector<passthrough::UplinkCount> Gateway::uplink_counts() const {
    return uplink_ ? uplink_->counts() : std::vector<passthrough::UplinkCount>{};
}

std::vector<BridgedTopic> Gateway::topics() const {
    std::vector<BridgedTopic> out;
    for (const std::shared_ptr<TopicBridge>& bridge : topics_->all()) {
        out.push_back(bridge->describe());
    }
    return out;
}

std::size_t Gateway::bridged_topics() const {
    return topics_->size();
}

std::size_t Gateway::scheduled_topics() const {
    return loop_->live_topics();
}

std::size_t Gateway::wan_topics() const {
    return wan_->topic_count();
}

std::vector<TopicCount> Gateway::topic_counts() const {
    return lifecycle_->topic_counts();
}

std::optional<BridgedTopic> Gateway::find_topic(const std::string& name) const {
    const std::shared_ptr<TopicBridge> bridge = topics_->find(name);
    return bridge != nullptr ? std::optional<BridgedTopic>(bridge->describe()) : std::nullopt;
}

bool Gateway::wait_for_topic(const std::string& name, std::chrono::milliseconds timeout) const {
    return topics_->wait_for(name, timeout);
}

core::TopicCounters Gateway::counters(core::TopicId id) const {
    return loop_->counters(id);
}

core::TopicCounters Gateway::total_counters() const {
    return loop_->total_counters();
}

std::size_t Gateway::queued_samples() const {
    return loop_->queued_samples();
}

std::int32_t Gateway::robot_matched_writers(core::TopicId id) const {
    const std::shared_ptr<TopicBridge> bridge = topics_->find(id);
    return bridge != nullptr ? bridge->matched_writers() : 0;
}

std::int32_t Gateway::wan_matched_readers(core::TopicId id) const {
    const std::shared_ptr<TopicBridge> bridge = topics_->find(id);
    return bridge != nullptr ? bridge->matched_readers() : 0;
}

eprosima::fastrtps::rtps::GuidPrefix_t Gateway::wan_guid_prefix() const {
    return wan_->guid_prefix();
}

std::size_t Gateway::wan_participants() const {
    return wan_->remote_participants();
}

std::optional<base::Duration> Gateway::wan_writer_lifespan(core::TopicId id, std::uint16_t lane) const {
    const std::shared_ptr<TopicBridge> bridge = topics_->find(id);
    return bridge != nullptr ? bridge->writer_lifespan(lane) : std::nullopt;
}

std::uint64_t Gateway::wan_write_failures() const {
    return sink_->wan_write_failures();
}

std::uint64_t Gateway::mean_wan_sample_wire_bytes() const {
    if (compact_) {
        const CompactWan::Stats stats = compact_->stats();
        return stats.bundles == 0 ? 0 : stats.wire_bytes / stats.bundles;
    }
    const core::TopicCounters sent = loop_->total_counters();
    return sent.forwarded == 0 ? 0 : sent.forwarded_wire_bytes / sent.forwarded;
}

std::optional<CompactWan::Stats> Gateway::wan_bundles() const {
    return compact_ ? std::optional<CompactWan::Stats>(compact_->stats()) : std::nullopt;
}

DatagramCoalescer::Counts Gateway::wan_datagrams() const {
    return wan_->coalescer().counts();
}

std::optional<ReceiverReportTotals> Gateway::receiver_report() const {
    return reports_ ? reports_->latest() : std::nullopt;
}

void Gateway::charge_unscheduled(std::uint64_t frame_bytes) {
    unscheduled_wire_bytes_.fetch_add(frame_bytes, std::memory_order_relaxed);
    charge_link(frame_bytes);
}

void Gateway::charge_link(std::uint64_t frame_bytes) {
    // A scheduled write's own extra (a reliable writer's HEARTBEAT, a copy to a second reader) is charged by the
    // writing thread once it is done: a hand-off per sample cost a thread's wake-up, 9 us here.
    core::ForwardingLoop* loop = charging_loop_.load();
    if (loop != nullptr && loop->charge_link_from_write(8u * frame_bytes)) {
        return;
    }
    pending_unscheduled_bytes_.fetch_add(frame_bytes, std::memory_order_relaxed);
    // One task charges whatever has come by the time it runs: a burst of copies costs one hand-off, not one each.
    if (!unscheduled_charge_posted_.exchange(true)) {
        worker_.post([this] {
            unscheduled_charge_posted_.store(false);
            loop_->charge_link(8u * pending_unscheduled_bytes_.exchange(0));
        });
    }
}

std::vector<TopicCount> Gateway::status_rows() const {
    // The topics bridged now, each with its earlier bridges' counts, and the retired ones in one row: the status
    // stays small whatever came and went, and its sums never go down.
    core::TopicCounters retired;
    std::vector<TopicCount> rows;
    for (TopicCount& row : lifecycle_->topic_counts()) {
        if (row.bridged) {
            rows.push_back(std::move(row));
        } else {
            retired += row.counters;
        }
    }
    if (retired.received > 0) {
        rows.push_back(TopicCount{RETIRED_TOPICS_ROW, passthrough::ResolvedTtl{}, retired, false, 0});
    }
    return rows;
}

void Gateway::publish_status_nts() {
    const auto now = std::chrono::steady_clock::now();
    worker_.post_at(now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(config_.status_period),
                    [this] { publish_status_nts(); });
    status_->look(now);
}

void Gateway::fill_status(idl::GatewayStatus& status, std::int32_t rows_readers) const {
    const auto prefix = wan_->guid_prefix();
    std::copy(std::begin(prefix.value), std::end(prefix.value), status.gateway_prefix().begin());
    {
        std::lock_guard<std::mutex> lock(sensor_mutex_);
        status.sensor(sensor_description_);
        status.sensor_detail(sensor_detail_);
        status.delivered_cap_bps(delivered_cap_bps_);
    }
    // The participant's announcements leave in the schedule but belong to no topic's demand: the grantor counts
    // them with the traffic outside it.
    status.unscheduled_wire_bytes(unscheduled_wire_bytes_.load() +
                                  loop_->repair_counters().announcements_sent_wire_bytes);
    status.uplink_topics(uplink_topics_.wan_topics());
    status.uplink_charged(config_.uplink_shares_link);
    std::uint64_t uplink_bytes = 0;
    for (const passthrough::UplinkCount& up : uplink_counts()) {
        uplink_bytes += up.wire_bytes;
    }
    status.uplink_wire_bytes(uplink_bytes);
    status.log_samples(logged());
    if (backfill_) {
        const core::BackfillPlanner::Backlog backlog = backfill_->backlog();
        const BackfillSender::Counts counts = backfill_->counts();
        status.backfill_rows(backlog.rows);
        status.backfill_bytes(backlog.bytes);
        status.backfill_oldest_ns(backlog.oldest ? base::to_ns(*backlog.oldest) : 0);
        status.backfill_sent(counts.sent);
        status.backfill_acknowledged(counts.acknowledged);
    }
    status.matched_readers(compact_ ? compact_->matched_readers() : rows_readers + status_writer_->matched_readers());
}

std::uint64_t Gateway::forwarded_robot_samples() const {
    if (compact_) {
        return compact_->stats().bundles;  // what the relay counts in compact mode
    }
    return lifecycle_->forwarded();
}

std::optional<Gateway::BackfillSummary> Gateway::backfill_summary() const {
    if (!backfill_) {
        return std::nullopt;
    }
    return BackfillSummary{loop_->counters(*backfill_topic_), backfill_->counts(), backfill_->backlog()};
}

core::TopicCounters Gateway::status_counters() const {
    return status_topic_ ? loop_->counters(*status_topic_) : core::TopicCounters{};
}

std::uint64_t Gateway::suppressed_repeats() const {
    return wan_->suppressed_repeats();
}

std::uint64_t Gateway::introductions() const {
    return wan_->introductions();
}

core::RepairCounters Gateway::repair_counters() const {
    return loop_->repair_counters();
}

std::optional<RepairDesk::Counts> Gateway::repair_desk_counts() const {
    if (RepairDesk* desk = wan_->repair_desk()) {
        return desk->counts();
    }
    return std::nullopt;
}

std::uint64_t Gateway::unscheduled_wire_bytes() const {
    return unscheduled_wire_bytes_.load();
}

std::uint64_t Gateway::logged() const {
    return sink_->logged();
}

core::LatencyHistogram::Snapshot Gateway::processing_latency() const {
    return sink_->processing_latency().snapshot();
}

}  // namespace tgw::dds
