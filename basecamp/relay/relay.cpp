#include "basecamp/relay/relay.hpp"

#include <algorithm>
#include <cstdio>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "base/config_error.hpp"
#include "base/dds_security.hpp"
#include "basecamp/capture/backfill_endpoints.hpp"
#include "basecamp/capture/receiver_reporter.hpp"
#include "basecamp/capture/wan_capture.hpp"
#include "basecamp/relay/compact_unpacker.hpp"
#include "basecamp/relay/metered_transport.hpp"
#include "passthrough/passthrough_qos.hpp"
#include "passthrough/passthrough_route.hpp"
#include "passthrough/passthrough_type.hpp"
#include "wire/backfill_topics.hpp"
#include "wire/compact_topics.hpp"
#include "wire/receiver_report_topic.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {

namespace fdds = eprosima::fastdds::dds;

/// One QoS offer of a topic: the WAN reader that asks for it, and the local writer that offers it, a passthrough
/// route that tallies, records and passes on every sample of the writers it carries.
class Relay::Lane final : public passthrough::PassthroughRoute {
  public:
    /// `store`: where --out records, or nullptr.
    Lane(const passthrough::LaneAssignment& writers, std::uint16_t index, TopicRecord topic, DeliveryTally& tally,
         SampleConsumer* store)
        : PassthroughRoute(topic.keyed),
          writers_(writers),
          index_(index),
          topic_(std::move(topic)),
          tally_(tally),
          store_(store) {}

    ChannelGrantor* statuses = nullptr;  ///< the lanes of tgw/status, with a channel rate
    passthrough::OfferedQos offer;
    std::atomic<std::uint64_t> relayed{0};
    std::atomic<std::uint64_t> failures{0};

  private:
    std::optional<eprosima::fastrtps::Time_t> admit(const passthrough::PassthroughData& data,
                                                    const fdds::SampleInfo& info) override {
        if (!writers_.carries(info.publication_handle, index_)) {
            return std::nullopt;  // the writer's own lane passes it on
        }
        if (info.valid_data) {
            tally_sample(tally_, topic_, info, data.payload.size());
            if (store_ != nullptr) {
                store_->add(sample_record(topic_, data.payload, info));
            }
            if (statuses != nullptr) {
                statuses->take_status(data.payload, data.payload.size());
            }
        }
        // SampleInfo carries the RTPS time type; the writers take the DDS one.
        return eprosima::fastrtps::Time_t(info.source_timestamp.seconds(), info.source_timestamp.nanosec());
    }

    void written(ReturnCode_t rc, bool /*reader_matched*/) override {
        if (rc == ReturnCode_t::RETCODE_OK) {
            relayed.fetch_add(1, std::memory_order_relaxed);
        } else if (failures.fetch_add(1, std::memory_order_relaxed) == 0) {
            std::fprintf(stderr, "tm-basecamp relay: a local write on '%s' failed (code %d)\n", topic_.topic.c_str(),
                         static_cast<int>(rc()));
        }
    }

    const passthrough::LaneAssignment& writers_;
    const std::uint16_t index_;
    const TopicRecord topic_;
    DeliveryTally& tally_;
    SampleConsumer* store_;
};

namespace {

/// A meter of the channel, and `qos`'s UDP transports made to show it every datagram they receive.
std::shared_ptr<ChannelMeter> metered(fdds::DomainParticipantQos& qos, double upper_bps, const base::Clock& clock) {
    auto meter = std::make_shared<ChannelMeter>(upper_bps, clock);
    bool any = false;
    for (auto& transport : qos.transport().user_transports) {
        if (std::dynamic_pointer_cast<eprosima::fastdds::rtps::UDPv4TransportDescriptor>(transport) == nullptr)
            continue;
        transport = std::make_shared<MeteredTransportDescriptor>(
            transport, [meter](const std::uint8_t* bytes, std::size_t size, const SourceAddress& from) {
                meter->datagram(bytes, size, from);
            });
        any = true;
    }
    if (!any)
        throw base::ConfigError("--measure-channel: the WAN participant has no UDP transport to measure");
    return meter;
}

}  // namespace

Relay::Relay(int wan_domain, fdds::DomainParticipantQos wan_qos, int local_domain, fdds::DomainParticipantQos local_qos,
             SampleConsumer* store, base::Duration report_period, const std::vector<std::string>& uplink,
             double channel_bps, bool measure_channel)
    : store_(store),
      wan_domain_(wan_domain),
      channel_bps_(channel_bps),
      measure_channel_(measure_channel),
      report_period_(report_period),
      uplink_topics_(uplink, "") {
    // The WAN participant first: Fast DDS 2.9 numbers a process's participants in the order they are made, and a
    // robot announces itself to the camp's participant 0 (telemetry-gateway --wan-peer-participants 1). What
    // either discovers waits in its queue until run() takes it, so neither may find the other missing.
    make_wan(std::move(wan_qos));
    local_qos.name("tm-basecamp relay/local");
    local_discovery_ = std::make_unique<passthrough::Discovery>(local_discovered_.callback());
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    local_ = factory->create_participant(local_domain, local_qos, local_discovery_.get(), fdds::StatusMask::none());
    if (local_ == nullptr) {
        reporter_.reset();
        grantor_.reset();
        wan_->set_listener(nullptr);
        wan_->delete_contained_entities();
        factory->delete_participant(wan_);
        throw base::ConfigError("--local-domain: cannot create a DDS participant on domain " +
                                std::to_string(local_domain));
    }
    local_discovery_->ignore_participant(local_->guid().guidPrefix);
    make_uplink();
}

void Relay::make_wan(fdds::DomainParticipantQos wan_qos) {
    discovery_ = std::make_unique<passthrough::Discovery>(discovered_.callback());
    wan_qos.name("tm-basecamp relay/wan");
    wan_secured_ = base::has_dds_security(wan_qos);
    if (channel_bps_ > 0 && measure_channel_) {
        meter_ = metered(wan_qos, channel_bps_, clock_);
        discovery_->on_participant([meter = meter_](const auto& /*prefix*/) { meter->participant_joined(); });
    }
    wan_ = fdds::DomainParticipantFactory::get_instance()->create_participant(wan_domain_, wan_qos, discovery_.get(),
                                                                              fdds::StatusMask::none());
    if (wan_ == nullptr) {
        throw base::ConfigError("--domain: cannot create a DDS participant on domain " + std::to_string(wan_domain_));
    }
    discovery_->ignore_participant(wan_->guid().guidPrefix);
    if (report_period_ > base::Duration::zero()) {
        reporter_ = std::make_unique<ReceiverReporter>(wan_);
    }
    if (channel_bps_ > 0) {
        grantor_ = std::make_unique<ChannelGrantor>(wan_, channel_bps_, clock_, meter_.get(), &tally_, store_);
    }
}

void Relay::make_uplink() {
    if (uplink_topics_.empty()) {
        return;
    }
    // Nothing is charged: the camp has no link budget. Its counts tell the grantor what the camp sends each robot.
    const core::WireModel wire = wan_secured_ ? core::WireModel{}.with_security() : core::WireModel{};
    uplink_ = std::make_unique<passthrough::Uplink>(local_, wan_, clock_, wire, passthrough::Uplink::Charge{});
    for (const passthrough::DiscoveredPublisher& publisher : uplink_publishers_) {
        route_uplink(publisher);
    }
}

void Relay::remake_wan(fdds::DomainParticipantQos wan_qos) {
    if (wan_ != nullptr) {
        retire_wan();
    }
    make_wan(std::move(wan_qos));
    make_uplink();
    if (archive_ != nullptr) {
        backfill_ = BackfillEndpoints::make_or_say_why(wan_, *archive_);
    }
    std::lock_guard<std::mutex> lock(topics_mutex_);
    const auto status = topics_.find(wire::STATUS_TOPIC);
    if (status != topics_.end()) {
        for (auto& lane : status->second->lanes)
            lane->statuses = grantor_.get();
    }
}

void Relay::retire_wan() {
    wan_->set_listener(nullptr);
    {
        // The readers first: none may take a sample into what goes next.
        std::lock_guard<std::mutex> lock(topics_mutex_);
        for (auto& [name, topic] : topics_) {
            for (auto& lane : topic->lanes) {
                lane->detach_reader();  // the local writer stays
                lane->statuses = nullptr;
            }
        }
        if (compact_) {
            for (const auto& [name, n] : compact_->relayed())
                relayed_by_earlier_unpackers_[name] += n;
        }
    }
    compact_.reset();  // its WAN readers and its local writers: made anew when a gateway's bundles appear again
    backfill_.reset();
    uplink_.reset();
    grantor_.reset();
    reporter_.reset();
    wan_subscribers_.forget();
    wan_->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(wan_);
    wan_ = nullptr;
    discovered_.take(std::chrono::milliseconds(0));  // the old participant's discoveries
}

Relay::~Relay() {
    for (fdds::DomainParticipant* participant : {wan_, local_}) {
        if (participant != nullptr)
            participant->set_listener(nullptr);
    }
    compact_.reset();  // its readers, then its writers
    backfill_.reset();
    uplink_.reset();
    grantor_.reset();
    {
        std::lock_guard<std::mutex> lock(topics_mutex_);
        topics_.clear();  // each lane's reader, then its writer
    }
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    for (fdds::DomainParticipant* participant : {wan_, local_}) {
        if (participant != nullptr) {
            participant->delete_contained_entities();
            factory->delete_participant(participant);
        }
    }
}

std::unique_ptr<Relay::Lane> Relay::make_lane(const passthrough::DiscoveredPublisher& publisher, Topic& topic,
                                              std::uint16_t index) {
    fdds::Topic* local_topic = passthrough::passthrough_topic(local_, publisher.topic, publisher.type_name,
                                                              publisher.keyed, publisher.type_object);
    fdds::Publisher* publisher_entity = local_publishers_.get(local_, publisher.qos);
    if (local_topic == nullptr || publisher_entity == nullptr) {
        std::fprintf(stderr, "tm-basecamp relay: cannot create the topic '%s' (type '%s')\n", publisher.topic.c_str(),
                     publisher.type_name.c_str());
        return nullptr;
    }
    auto lane = std::make_unique<Lane>(topic.writers, index, topic_record(publisher), tally_, store_);
    lane->offer = publisher.qos;
    if (publisher.topic == wire::STATUS_TOPIC) {
        lane->statuses = grantor_.get();
    }
    // The writer first, so that nothing the reader takes finds no writer. Its Lifespan is the gateway's (TTL, or
    // none on a latched topic): with the source timestamp kept, a sample expires here when it would have there.
    const bool writing =
        lane->open_writer(*publisher_entity, local_topic,
                          passthrough::passthrough_writer_qos(publisher_entity->get_default_datawriter_qos(),
                                                              publisher.qos, publisher.keyed, publisher.lifespan));
    if (!writing || !attach_reader(*lane, publisher)) {
        std::fprintf(stderr, "tm-basecamp relay: cannot relay '%s' (%s)\n", publisher.topic.c_str(),
                     publisher.qos.describe().c_str());
        return nullptr;
    }
    return lane;
}

bool Relay::attach_reader(Lane& lane, const passthrough::DiscoveredPublisher& publisher) {
    fdds::Topic* wan_topic =
        passthrough::passthrough_topic(wan_, publisher.topic, publisher.type_name, publisher.keyed);
    fdds::Subscriber* subscriber = wan_subscribers_.get(wan_, publisher.qos);
    if (wan_topic == nullptr || subscriber == nullptr) {
        return false;
    }
    return lane.attach_reader(
        *subscriber, wan_topic,
        passthrough::passthrough_reader_qos(subscriber->get_default_datareader_qos(), publisher.qos, publisher.keyed));
}

void Relay::relay(const passthrough::DiscoveredPublisher& publisher) {
    // Receivers' reports are for the gateways, not the camp. Backfill is past its TTL: the archive's, never the
    // camp's live domain (archive_backfill).
    if (publisher.topic == wire::RECEIVER_REPORT_TOPIC || wire::is_backfill_topic(publisher.topic)) {
        return;
    }
    // A compact-mode gateway: its bundles are unpacked, each sample republished on its own topic.
    if (publisher.topic == wire::COMPACT_BUNDLE_TOPIC || publisher.topic == wire::COMPACT_CATALOG_TOPIC) {
        if (!compact_) {
            compact_ = std::make_unique<CompactUnpacker>(wan_, local_, local_publishers_, tally_, store_,
                                                         grantor_.get(), archive_);
        }
        return;
    }
    std::unique_lock<std::mutex> lock(topics_mutex_);
    auto& topic = topics_[publisher.topic];
    if (!topic) {
        topic = std::make_unique<Topic>();
    }
    for (std::size_t i = 0; i < topic->lanes.size(); ++i) {
        Lane& lane = *topic->lanes[i];
        if (lane.offer == publisher.qos) {
            topic->writers.assign(publisher.writer, static_cast<std::uint16_t>(i));
            // A lane whose WAN participant was made anew reads again on the new one; its local writer never left.
            if (!lane.has_reader()) {
                lock.unlock();  // entity creation may call back into discovery
                if (!attach_reader(lane, publisher)) {
                    std::fprintf(stderr, "tm-basecamp relay: cannot relay '%s' again (%s)\n", publisher.topic.c_str(),
                                 publisher.qos.describe().c_str());
                }
            }
            return;
        }
    }
    const auto index = static_cast<std::uint16_t>(topic->lanes.size());
    lock.unlock();  // entity creation may call back into discovery
    std::unique_ptr<Lane> lane = make_lane(publisher, *topic, index);
    if (!lane) {
        return;
    }
    if (store_ != nullptr && index == 0) {
        store_->add_topic(topic_record(publisher));
    }
    topic->writers.assign(publisher.writer, index);
    lock.lock();
    topic->lanes.push_back(std::move(lane));
}

void Relay::uplink(const passthrough::DiscoveredPublisher& publisher) {
    if (uplink_topics_.empty() || !uplink_topics_.robot_topic(publisher.topic)) {
        return;  // nothing else goes from the camp onto the WAN
    }
    uplink_publishers_.push_back(publisher);
    if (uplink_) {  // none while a WAN participant could not be made anew: routed when one is
        route_uplink(publisher);
    }
}

void Relay::route_uplink(const passthrough::DiscoveredPublisher& publisher) {
    // The camp publisher's Lifespan goes on with its commands; without one they never expire here, and the gateway
    // gives them its own TTL.
    std::optional<passthrough::ResolvedTtl> ttl;
    if (publisher.lifespan) {
        ttl = passthrough::ResolvedTtl{*publisher.lifespan, passthrough::TtlSource::publisher};
    }
    uplink_->route(publisher, publisher.topic, ttl);
}

void Relay::archive_backfill(BackfillArchive& archive) {
    backfill_ = BackfillEndpoints::make_or_say_why(wan_, archive);
    archive_ = backfill_ ? &archive : nullptr;
}

core::ChannelGrants Relay::channel_grants() const {
    return grantor_ ? grantor_->last_grants() : core::ChannelGrants{};
}

std::optional<double> Relay::newcomer_share() const {
    return grantor_ ? std::optional<double>(grantor_->newcomer_share()) : std::nullopt;
}

std::optional<ChannelReading> Relay::channel_reading() const {
    return grantor_ ? grantor_->channel_reading() : std::nullopt;
}

std::vector<passthrough::UplinkCount> Relay::uplink_counts() const {
    return uplink_ ? uplink_->counts() : std::vector<passthrough::UplinkCount>{};
}

void Relay::run(base::Duration duration, const std::atomic<bool>& stop) {
    const auto end = base::SteadyClock::now() + duration;
    while (!stop.load() && base::SteadyClock::now() < end) {
        for (const passthrough::DiscoveredPublisher& publisher : discovered_.take(std::chrono::milliseconds(100))) {
            relay(publisher);
        }
        if (compact_) {
            compact_->poll();
        }
        if (grantor_) {
            if (uplink_) {
                grantor_->commands_sent(uplink_->counts());
            }
            grantor_->poll();
        }
        for (const passthrough::DiscoveredPublisher& publisher : local_discovered_.take(std::chrono::milliseconds(0))) {
            uplink(publisher);
        }
        if (backfill_) {
            backfill_->publish_acks_when_due();
        }
        if (reporter_ && base::SteadyClock::now() >= next_report_) {
            next_report_ += report_period_;
            reporter_->publish(tally_.totals());
        }
    }
}

std::int32_t Relay::local_readers(const std::string& topic) const {
    std::lock_guard<std::mutex> lock(topics_mutex_);
    const auto it = topics_.find(topic);
    std::int32_t n = 0;
    if (it != topics_.end()) {
        for (const auto& lane : it->second->lanes) {
            n += lane->readers_matched();
        }
    }
    return n + (compact_ ? compact_->local_readers(topic) : 0);
}

std::map<std::string, std::uint64_t> Relay::relayed() const {
    std::lock_guard<std::mutex> lock(topics_mutex_);
    std::map<std::string, std::uint64_t> counts;
    for (const auto& [name, topic] : topics_) {
        std::uint64_t n = 0;
        for (const auto& lane : topic->lanes) {
            n += lane->relayed.load();
        }
        counts[name] = n;
    }
    if (compact_) {
        for (const auto& [name, n] : compact_->relayed()) {
            counts[name] += n;
        }
    }
    for (const auto& [name, n] : relayed_by_earlier_unpackers_) {
        counts[name] += n;
    }
    return counts;
}

}  // namespace tgw::basecamp
