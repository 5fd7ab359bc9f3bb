#include "gateway/dds/gateway.hpp"

#include <algorithm>
#include <iostream>
#include <utility>

#include "gateway/core/config_error.hpp"
#include "gateway/dds/dds_time.hpp"
#include "gateway/dds/gateway_sink.hpp"
#include "gateway/dds/qos_file.hpp"
#include "gateway/dds/receiver_report_topic.hpp"
#include "gateway/dds/robot_participant.hpp"
#include "gateway/dds/topic_bridge.hpp"
#include "gateway/dds/topic_directory.hpp"
#include "gateway/dds/wan_address.hpp"
#include "gateway/dds/wan_router.hpp"
#include "gateway/log/robot_log.hpp"

namespace tgw::dds {

namespace {

// Fast DDS accepts domain ids whose well-known ports fit in 16 bits.
constexpr int MAX_DOMAIN_ID = 232;

void check_domain(const char* flag, int domain) {
    if (domain < 0 || domain > MAX_DOMAIN_ID) {
        throw core::ConfigError(std::string(flag) + " " + std::to_string(domain) + ": must be 0 to " +
                                std::to_string(MAX_DOMAIN_ID));
    }
}

}  // namespace

void GatewayConfig::validate() const {
    check_domain("--robot-domain", robot_domain);
    check_domain("--wan-domain", wan_domain);
    if (robot_domain == wan_domain) {
        // One domain would make the gateway read its own WAN writers back.
        throw core::ConfigError("--wan-domain " + std::to_string(wan_domain) + ": must differ from --robot-domain");
    }
    const std::size_t datagram = scheduler.wire.max_datagram_bytes;
    if (datagram < core::WireModel::MIN_DATAGRAM_PAYLOAD_BYTES || datagram > core::WireModel::MAX_UDP_PAYLOAD_BYTES) {
        throw core::ConfigError("--wan-max-datagram " + std::to_string(datagram) + ": expected " +
                                std::to_string(core::WireModel::MIN_DATAGRAM_PAYLOAD_BYTES) + " to " +
                                std::to_string(core::WireModel::MAX_UDP_PAYLOAD_BYTES) + " bytes");
    }
    if (robot.receive_buffer_bytes < RobotTransport::MIN_RECEIVE_BUFFER_BYTES ||
        robot.receive_buffer_bytes > RobotTransport::MAX_RECEIVE_BUFFER_BYTES) {
        throw core::ConfigError("--robot-receive-buffer " + std::to_string(robot.receive_buffer_bytes) + ": expected " +
                                std::to_string(RobotTransport::MIN_RECEIVE_BUFFER_BYTES) + " to " +
                                std::to_string(RobotTransport::MAX_RECEIVE_BUFFER_BYTES) + " bytes");
    }
    if (wan_coalesce_window < std::chrono::microseconds::zero() || wan_coalesce_window > MAX_COALESCE_WINDOW) {
        throw core::ConfigError("--wan-coalesce-us " + std::to_string(wan_coalesce_window.count()) +
                                ": expected 0 to " + std::to_string(MAX_COALESCE_WINDOW.count()) + " microseconds");
    }
    if (default_ttl <= core::Duration::zero()) {
        throw core::ConfigError("--default-ttl: must be positive");
    }
    for (const std::string& peer : wan_peers) {
        parse_wan_peer(peer, wan_domain);
    }
    for (const auto* globs : {&allow, &deny}) {
        for (const std::string& glob : *globs) {
            if (glob.empty()) {
                throw core::ConfigError(std::string(globs == &allow ? "--allow" : "--deny") + ": empty glob");
            }
        }
    }
}

struct Gateway::Bridge {
    BridgedTopic info;
    std::unique_ptr<TopicBridge> listener;
    eprosima::fastdds::dds::DataReader* reader = nullptr;
};

Gateway::Gateway(GatewayConfig config, const core::Clock& clock)
    : config_(std::move(config)), clock_(clock), filter_(config_.allow, config_.deny) {
    config_.validate();
    if (!config_.log_file.empty()) {
        log_ = std::make_unique<log::RobotLog>(config_.log_file);
    }
    if (!config_.qos_file.empty()) {
        load_qos_file(config_.qos_file);
    }

    WanConfig wan;
    wan.domain = config_.wan_domain;
    for (const std::string& peer : config_.wan_peers) {
        wan.peers.push_back(parse_wan_peer(peer, config_.wan_domain));
    }
    if (!config_.wan_interface.empty()) {
        wan.interface_address = resolve_interface_address(config_.wan_interface);
    }
    wan.listen_port = config_.wan_port;
    wan.lease_duration = config_.wan_lease;
    wan.announcement_period = config_.wan_announcement_period;
    wan.max_datagram_bytes = config_.scheduler.wire.max_datagram_bytes;
    wan.coalesce_window = config_.wan_coalesce_window;
    wan_ = std::make_unique<WanRouter>(wan, participant_profile(WAN_PARTICIPANT_PROFILE));

    directory_ = std::make_unique<TopicDirectory>();
    sink_ = std::make_unique<GatewaySink>(*wan_, log_.get(), *directory_, clock_);
    loop_ = std::make_unique<core::ForwardingLoop>(config_.scheduler, clock_, *sink_);
    loop_->start();
    if (config_.receiver_reports) {
        // After the loop: each report is compared with what the loop had forwarded when it came.
        reports_ = std::make_unique<ReceiverReportReader>(wan_->guid_prefix(),
                                                          [this] { return loop_->total_counters().forwarded; });
        if (!wan_->subscribe_receiver_reports(reports_.get())) {
            throw core::ConfigError("--receiver-reports: cannot subscribe to the base camp's reports");
        }
        // The report reader's announcement crosses the link once per peer, as a writer's does.
        loop_->charge_link(8u *
                           config_.scheduler.wire.announcement_bytes(std::string(RECEIVER_REPORT_TOPIC).size(),
                                                                     std::string("tgw::idl::ReceiverReport").size()) *
                           std::max<std::size_t>(1, config_.wan_peers.size()));
    }

    discovery_ = std::make_unique<Discovery>([this](DiscoveredPublisher&& pub) { on_publisher(std::move(pub)); });
    discovery_->ignore_participant(wan_->guid_prefix());
    worker_ = std::thread([this] { run_worker(); });
    try {
        RobotTransport transport = config_.robot;
        for (std::string& interface : transport.interfaces) {
            interface = resolve_interface_address(interface, "--robot-interface");
        }
        robot_ = std::make_unique<RobotParticipant>(config_.robot_domain, discovery_.get(), transport,
                                                    participant_profile(ROBOT_PARTICIPANT_PROFILE));
        discovery_->ignore_participant(robot_->guid_prefix());
    } catch (...) {
        stop();
        throw;
    }
}

Gateway::~Gateway() {
    stop();
}

void Gateway::stop() {
    std::lock_guard<std::mutex> lock(stop_mutex_);
    if (stopped_) {
        return;
    }
    stopped_ = true;
    stop_worker();
    if (robot_) {
        std::lock_guard<std::mutex> bridges_lock(bridges_mutex_);
        for (auto& [name, bridge] : bridges_) {
            robot_->delete_reader(bridge->reader);
            bridge->reader = nullptr;
        }
    }
    robot_.reset();
    loop_->stop();
    if (log_) {
        log_->flush();
    }
}

void Gateway::observe_link_backlog(std::uint64_t bytes) {
    loop_->observe_link_backlog(8u * bytes);
}

void Gateway::apply_reading(const sensor::RateReading& reading) {
    set_rate(reading.rate_bps);
    if (reading.queued_bytes) {
        observe_link_backlog(*reading.queued_bytes);
    }
}

double Gateway::rate_bps() const {
    return loop_->rate_bps();
}

void Gateway::set_rate(double rate_bps) {
    loop_->set_rate(rate_bps);
}

void Gateway::on_publisher(DiscoveredPublisher&& pub) {
    {
        std::lock_guard<std::mutex> lock(events_mutex_);
        events_.push_back(std::move(pub));
    }
    events_changed_.notify_one();
}

void Gateway::stop_worker() {
    {
        std::lock_guard<std::mutex> lock(events_mutex_);
        worker_stopping_ = true;
    }
    events_changed_.notify_all();
    if (worker_.joinable()) {
        worker_.join();
    }
}

void Gateway::run_worker() {
    std::unique_lock<std::mutex> lock(events_mutex_);
    while (true) {
        events_changed_.wait(lock, [this] { return worker_stopping_ || !events_.empty(); });
        if (worker_stopping_) {
            return;
        }
        DiscoveredPublisher pub = std::move(events_.front());
        events_.pop_front();
        lock.unlock();
        bridge_nts(pub);
        lock.lock();
    }
}

void Gateway::bridge_nts(const DiscoveredPublisher& pub) {
    if (!filter_.admits(pub.topic)) {
        return;
    }
    {
        std::lock_guard<std::mutex> lock(bridges_mutex_);
        if (bridges_.count(pub.topic) != 0) {
            return;  // a further publisher on a bridged topic: the reader matches it already
        }
    }
    // The robot participant exists once discovery reports anything; stop() joins this thread before
    // resetting it.
    if (!robot_) {
        return;
    }

    std::optional<core::Duration> profile_lifespan;
    if (auto profile = wan_->writer_profile(pub.topic)) {
        profile_lifespan = to_duration(profile->lifespan().duration);
    }
    const ResolvedTtl ttl = resolve_ttl(profile_lifespan, pub.lifespan, config_.default_ttl);

    auto bridge = std::make_unique<Bridge>();
    bridge->info.name = pub.topic;
    bridge->info.type_name = pub.type_name;
    bridge->info.keyed = pub.keyed;
    bridge->info.ttl = ttl;
    bridge->info.id = loop_->add_topic(core::TopicConfig{pub.topic, ttl.ttl});
    directory_->add(bridge->info.id, {pub.topic, pub.type_name});

    // The WAN writer first, so that nothing the reader takes finds no writer.
    if (!wan_->add_topic(bridge->info.id, pub.topic, pub.type_name, pub.keyed, ttl.ttl)) {
        return;
    }
    // The new writer's SEDP announcement goes to every peer over the same slow link as the samples.
    const std::size_t announcement = config_.scheduler.wire.announcement_bytes(pub.topic.size(), pub.type_name.size());
    loop_->charge_link(8u * announcement * std::max<std::size_t>(1, config_.wan_peers.size()));
    bridge->listener = std::make_unique<TopicBridge>(bridge->info.id, pub.keyed, *loop_, clock_);
    bridge->reader = robot_->create_reader(pub, bridge->listener.get());
    if (bridge->reader == nullptr) {
        return;
    }
    {
        std::lock_guard<std::mutex> lock(bridges_mutex_);
        if (by_id_.size() <= bridge->info.id) {
            by_id_.resize(bridge->info.id + 1);
        }
        by_id_[bridge->info.id] = bridge->info;
        bridges_.emplace(pub.topic, std::move(bridge));
    }
    bridges_changed_.notify_all();
}

std::vector<BridgedTopic> Gateway::topics() const {
    std::lock_guard<std::mutex> lock(bridges_mutex_);
    std::vector<BridgedTopic> out;
    for (const auto& [name, bridge] : bridges_) {
        out.push_back(bridge->info);
    }
    return out;
}

std::optional<BridgedTopic> Gateway::find_topic(const std::string& name) const {
    std::lock_guard<std::mutex> lock(bridges_mutex_);
    const auto it = bridges_.find(name);
    if (it == bridges_.end()) {
        return std::nullopt;
    }
    return it->second->info;
}

bool Gateway::wait_for_topic(const std::string& name, std::chrono::milliseconds timeout) const {
    std::unique_lock<std::mutex> lock(bridges_mutex_);
    return bridges_changed_.wait_for(lock, timeout, [&] { return bridges_.count(name) != 0; });
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
    std::lock_guard<std::mutex> lock(bridges_mutex_);
    for (const auto& [name, bridge] : bridges_) {
        if (bridge->info.id == id) {
            return bridge->listener->matched_writers();
        }
    }
    return 0;
}

std::int32_t Gateway::wan_matched_readers(core::TopicId id) const {
    return wan_->matched_readers(id);
}

std::optional<core::Duration> Gateway::wan_writer_lifespan(core::TopicId id) const {
    return wan_->writer_lifespan(id);
}

std::uint64_t Gateway::wan_write_failures() const {
    return sink_->wan_write_failures();
}

DatagramCoalescer::Counts Gateway::wan_datagrams() const {
    return wan_->coalescer().counts();
}

std::optional<ReceiverReportTotals> Gateway::receiver_report() const {
    return reports_ ? reports_->latest() : std::nullopt;
}

std::uint64_t Gateway::logged() const {
    return sink_->logged();
}

core::LatencyHistogram::Snapshot Gateway::processing_latency() const {
    return sink_->processing_latency().snapshot();
}

}  // namespace tgw::dds
