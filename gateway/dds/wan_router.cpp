#include "gateway/dds/wan_router.hpp"

#include <algorithm>
#include <iostream>
#include <utility>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include "ReceiverReportPubSubTypes.h"
#include "gateway/core/config_error.hpp"
#include "gateway/core/wire_model.hpp"
#include "gateway/dds/coalescing_transport.hpp"
#include "gateway/dds/dds_time.hpp"
#include "gateway/dds/passthrough_type.hpp"
#include "gateway/dds/receiver_report_topic.hpp"

namespace tgw::dds {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastdds::rtps::UDPv4TransportDescriptor;
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;
using eprosima::fastrtps::types::ReturnCode_t;

class WanRouter::WriterListener final : public fdds::DataWriterListener {
  public:
    void on_publication_matched(fdds::DataWriter* /*writer*/, const fdds::PublicationMatchedStatus& info) override {
        matched.store(info.current_count);
    }
    std::atomic<std::int32_t> matched{0};
};

struct WanRouter::Entry {
    std::string topic;
    bool keyed = false;
    fdds::DataWriter* writer = nullptr;
    WriterListener listener;
    bool failure_reported = false;
};

namespace {

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
    : coalescer_(std::make_shared<DatagramCoalescer>(config.coalesce_window, config.max_datagram_bytes, clock_)) {
    fdds::DomainParticipantQos qos =
        base ? *base : fdds::DomainParticipantFactory::get_instance()->get_default_participant_qos();
    qos.name("telemetry-gateway/wan");

    // UDPv4 only: no shared memory (the base camp is elsewhere), bound to the WAN interface.
    qos.transport().use_builtin_transports = false;
    qos.transport().user_transports.clear();
    auto udp = std::make_shared<UDPv4TransportDescriptor>();
    // By default one RTPS message per Ethernet frame: larger samples go as DATA_FRAG, which the wire model
    // counts and a reliable writer can repair one by one, instead of IP fragments of one 64 kB datagram.
    udp->maxMessageSize = static_cast<std::uint32_t>(config.max_datagram_bytes);
    if (!config.interface_address.empty()) {
        udp->interfaceWhiteList.push_back(config.interface_address);
    }
    qos.transport().user_transports.push_back(std::make_shared<CoalescingTransportDescriptor>(udp, coalescer_));

    // An explicit metatraffic unicast locator and no multicast one: Fast DDS then opens no multicast
    // listener and announces only to the initial peers. Port 0 means the participant id's well-known port.
    auto& builtin = qos.wire_protocol().builtin;
    builtin.metatrafficMulticastLocatorList.clear();
    builtin.metatrafficUnicastLocatorList.clear();
    builtin.metatrafficUnicastLocatorList.push_back(udp_locator(config.interface_address, config.listen_port));
    qos.wire_protocol().default_multicast_locator_list.clear();
    builtin.initialPeersList.clear();
    for (const WanPeer& peer : config.peers) {
        builtin.initialPeersList.push_back(udp_locator(peer.address, peer.port));
    }
    if (!base) {
        // A participant profile from the --qos file sets its own discovery timing.
        builtin.discovery_config.leaseDuration = to_dds_duration(config.lease_duration);
        builtin.discovery_config.leaseDuration_announcementperiod = to_dds_duration(config.announcement_period);
    }

    participant_ = fdds::DomainParticipantFactory::get_instance()->create_participant(
        static_cast<fdds::DomainId_t>(config.domain), qos, nullptr, fdds::StatusMask::none());
    if (participant_ == nullptr) {
        throw core::ConfigError("--wan-domain " + std::to_string(config.domain) +
                                ": cannot create the WAN participant (check --wan-interface and --wan-peer)");
    }
    publisher_ = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    if (publisher_ == nullptr) {
        fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
        throw core::ConfigError("--wan-domain " + std::to_string(config.domain) + ": cannot create a publisher");
    }
    coalescer_->start();
}

WanRouter::~WanRouter() {
    // Sends what waits while the transport's channels still exist.
    coalescer_->stop();
    if (participant_ != nullptr) {
        participant_->delete_contained_entities();
        fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
    }
}

std::optional<fdds::DataWriterQos> WanRouter::writer_profile(const std::string& topic) const {
    fdds::DataWriterQos qos;
    if (publisher_->get_datawriter_qos_from_profile(topic, qos) != ReturnCode_t::RETCODE_OK) {
        return std::nullopt;
    }
    return qos;
}

bool WanRouter::add_topic(core::TopicId id, const std::string& topic, const std::string& type_name, bool keyed,
                          core::Duration ttl) {
    auto entry = std::make_unique<Entry>();
    entry->topic = topic;
    entry->keyed = keyed;

    fdds::TypeSupport type = participant_->find_type(type_name);
    if (type.empty()) {
        type = fdds::TypeSupport(new PassthroughType(type_name, keyed));
        if (participant_->register_type(type, type_name) != ReturnCode_t::RETCODE_OK) {
            std::cerr << "telemetry-gateway: cannot register WAN type " << type_name << " for " << topic << '\n';
            return false;
        }
    }
    fdds::Topic* wan_topic = participant_->create_topic(topic, type_name, fdds::TOPIC_QOS_DEFAULT);
    if (wan_topic == nullptr) {
        std::cerr << "telemetry-gateway: cannot create WAN topic " << topic << '\n';
        return false;
    }

    fdds::DataWriterQos qos;
    if (auto profile = writer_profile(topic)) {
        qos = *profile;
    } else {
        qos = publisher_->get_default_datawriter_qos();
        // Best effort by default: no HEARTBEAT/ACKNACK on a slow link; the scheduler already decided what
        // is worth sending, and a late retransmission would be stale.
        qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
        qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
        qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        qos.history().depth = 1;
    }
    qos.lifespan().duration = to_dds_duration(ttl);
    qos.endpoint().history_memory_policy = eprosima::fastrtps::rtps::DYNAMIC_REUSABLE_MEMORY_MODE;
    qos.data_sharing().off();

    entry->writer = publisher_->create_datawriter(wan_topic, qos, &entry->listener, fdds::StatusMask::all());
    if (entry->writer == nullptr) {
        std::cerr << "telemetry-gateway: cannot create the WAN writer for " << topic << '\n';
        participant_->delete_topic(wan_topic);
        return false;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (entries_.size() <= id) {
        entries_.resize(id + 1);
    }
    entries_[id] = std::move(entry);
    return true;
}

WanRouter::Entry* WanRouter::entry(core::TopicId id) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return id < entries_.size() ? entries_[id].get() : nullptr;
}

WriteResult WanRouter::write(core::Sample&& sample) {
    Entry* e = entry(sample.topic);
    if (e == nullptr) {
        write_failures_.fetch_add(1, std::memory_order_relaxed);
        return WriteResult::unknown_topic;
    }
    PassthroughData data;
    // The sample is done with once written: its buffer moves, and Fast DDS copies it once into the change.
    data.payload = std::move(sample.payload);
    fdds::InstanceHandle_t handle = fdds::HANDLE_NIL;
    if (e->keyed) {
        if (sample.key.valid) {
            for (std::size_t i = 0; i < sample.key.bytes.size(); ++i) {
                data.key.value[i] = sample.key.bytes[i];
            }
        }
        handle = data.key.isDefined() ? data.key : PassthroughType::UNKNOWN_INSTANCE;
    }
    const ReturnCode_t rc = [&] {
        const DatagramCoalescer::DeferScope may_wait;
        return e->writer->write_w_timestamp(&data, handle, to_dds_time(sample.source_time));
    }();
    if (rc != ReturnCode_t::RETCODE_OK) {
        write_failures_.fetch_add(1, std::memory_order_relaxed);
        if (!e->failure_reported) {
            e->failure_reported = true;
            std::cerr << "telemetry-gateway: WAN write failed on " << e->topic << " (code " << rc() << ")\n";
        }
        return WriteResult::failed;
    }
    return WriteResult::ok;
}

bool WanRouter::subscribe_receiver_reports(fdds::DataReaderListener* listener) {
    fdds::TypeSupport type(new idl::ReceiverReportPubSubType());
    if (participant_->register_type(type) != ReturnCode_t::RETCODE_OK) {
        std::cerr << "telemetry-gateway: cannot register the receiver report type\n";
        return false;
    }
    fdds::Topic* topic =
        participant_->create_topic(RECEIVER_REPORT_TOPIC, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    fdds::Subscriber* subscriber = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    if (topic == nullptr || subscriber == nullptr) {
        std::cerr << "telemetry-gateway: cannot subscribe to " << RECEIVER_REPORT_TOPIC << '\n';
        return false;
    }
    fdds::DataReaderQos qos = subscriber->get_default_datareader_qos();
    // Best effort and the latest per receiver: every report carries all the counts.
    qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
    qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
    qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    qos.history().depth = 1;
    qos.data_sharing().off();
    qos.expects_inline_qos(false);
    if (subscriber->create_datareader(topic, qos, listener) == nullptr) {
        std::cerr << "telemetry-gateway: cannot create the reader of " << RECEIVER_REPORT_TOPIC << '\n';
        return false;
    }
    return true;
}

std::optional<core::Duration> WanRouter::writer_lifespan(core::TopicId id) const {
    Entry* e = entry(id);
    if (e == nullptr) {
        return std::nullopt;
    }
    return to_duration(e->writer->get_qos().lifespan().duration);
}

std::int32_t WanRouter::matched_readers(core::TopicId id) const {
    Entry* e = entry(id);
    return e == nullptr ? 0 : e->listener.matched.load();
}

eprosima::fastrtps::rtps::GuidPrefix_t WanRouter::guid_prefix() const {
    return participant_->guid().guidPrefix;
}

}  // namespace tgw::dds
