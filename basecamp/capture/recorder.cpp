#include "basecamp/capture/recorder.hpp"

#include <algorithm>
#include <cstdio>
#include <iterator>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "base/config_error.hpp"
#include "basecamp/capture/backfill_endpoints.hpp"
#include "basecamp/capture/camp_participant.hpp"
#include "basecamp/capture/receiver_reporter.hpp"
#include "basecamp/capture/wan_capture.hpp"
#include "passthrough/dds_time.hpp"
#include "passthrough/passthrough_type.hpp"
#include "passthrough/take_each.hpp"
#include "wire/backfill_topics.hpp"
#include "wire/receiver_report_topic.hpp"

namespace tgw::basecamp {

namespace fdds = eprosima::fastdds::dds;

/// The reader of one topic and its listener: takes every sample and hands it to the store.
class Recorder::TopicReader final : public fdds::DataReaderListener {
  public:
    TopicReader(const passthrough::DiscoveredPublisher& publisher, SampleConsumer& store, DeliveryTally& tally)
        : topic_(topic_record(publisher)), store_(store), tally_(tally) {}

    void on_data_available(fdds::DataReader* reader) override {
        passthrough::take_valid<passthrough::PassthroughData>(
            *reader, [this](passthrough::PassthroughData& data, const fdds::SampleInfo& info) {
                tally_sample(tally_, topic_, info, data.payload.size());
                store_.add(sample_record(topic_, std::move(data.payload), info));
                ++received;
            });
    }

    void on_subscription_matched(fdds::DataReader* /*reader*/, const fdds::SubscriptionMatchedStatus& info) override {
        matched.store(info.current_count);
    }

    const TopicRecord& topic() const { return topic_; }

    std::atomic<std::uint64_t> received{0};
    std::atomic<std::int32_t> matched{0};

  private:
    TopicRecord topic_;
    SampleConsumer& store_;
    DeliveryTally& tally_;
};

Recorder::Recorder(int domain, const base::PeerTransport& transport, SampleConsumer& store,
                   base::Duration report_period, const std::optional<base::SecurityFiles>& security)
    : store_(store), report_period_(report_period) {
    discovery_ = std::make_unique<passthrough::Discovery>(discovered_.callback());
    participant_ = create_camp_participant(domain, transport, security, "tm-basecamp", *discovery_);
    subscriber_ = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    if (subscriber_ == nullptr)
        throw base::ConfigError("cannot create a DDS subscriber");
    if (report_period_ > base::Duration::zero())
        reporter_ = std::make_unique<ReceiverReporter>(participant_);
}

Recorder::~Recorder() {
    stop();
}

void Recorder::archive_backfill(BackfillArchive& archive) {
    backfill_ = BackfillEndpoints::make_or_say_why(participant_, archive);
}

void Recorder::stop() {
    backfill_.reset();
    if (participant_ != nullptr) {
        participant_->set_listener(nullptr);
        participant_->delete_contained_entities();
        fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
        participant_ = nullptr;
    }
}

void Recorder::subscribe(const passthrough::DiscoveredPublisher& publisher) {
    // Other receivers' reports are for their gateways, not a recording. Backfill is read by its own endpoints
    // (archive_backfill), or not at all: a plain reader would have the gateway send rows no one acknowledges.
    if (readers_.count(publisher.topic) != 0 || publisher.topic == wire::RECEIVER_REPORT_TOPIC ||
        wire::is_backfill_topic(publisher.topic))
        return;
    if (!only_.empty() && std::find(only_.begin(), only_.end(), publisher.topic) == only_.end())
        return;
    fdds::Topic* topic =
        passthrough::passthrough_topic(participant_, publisher.topic, publisher.type_name, publisher.keyed);
    if (topic == nullptr) {
        std::fprintf(stderr, "tm-basecamp: cannot create topic '%s' (type '%s')\n", publisher.topic.c_str(),
                     publisher.type_name.c_str());
        return;
    }
    fdds::DataReaderQos qos = subscriber_->get_default_datareader_qos();
    // Match the writer as it is: a reliable writer gets a reliable reader, so the link carries what it would
    // carry for any base-camp subscriber. The reader keeps late samples: they are what the report measures.
    qos.reliability().kind =
        publisher.qos.reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
    qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
    qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    qos.history().depth = 1000;
    // Unlimited: Fast DDS refuses a keyed reader whose max_samples is below max_instances x per instance.
    qos.resource_limits().max_samples = fdds::LENGTH_UNLIMITED;
    qos.resource_limits().max_instances = 1000;
    qos.resource_limits().max_samples_per_instance = 1000;
    qos.endpoint().history_memory_policy = eprosima::fastrtps::rtps::DYNAMIC_REUSABLE_MEMORY_MODE;
    qos.data_sharing().off();
    // Cyclone DDS 0.10 refuses readers that expect inline QoS (docs/design.md §7).
    qos.expects_inline_qos(false);

    auto reader = std::make_unique<TopicReader>(publisher, store_, tally_);
    if (subscriber_->create_datareader(topic, qos, reader.get()) == nullptr) {
        std::fprintf(stderr, "tm-basecamp: cannot create a reader for '%s'\n", publisher.topic.c_str());
        return;
    }
    store_.add_topic(reader->topic());
    std::lock_guard<std::mutex> lock(readers_mutex_);
    readers_.emplace(publisher.topic, std::move(reader));
}

void Recorder::run(base::Duration duration, const std::atomic<bool>& stop) {
    const auto end = base::SteadyClock::now() + duration;
    while (!stop.load() && base::SteadyClock::now() < end) {
        for (const passthrough::DiscoveredPublisher& publisher : discovered_.take(std::chrono::milliseconds(100))) {
            subscribe(publisher);
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

std::map<std::string, std::uint64_t> Recorder::received() const {
    std::lock_guard<std::mutex> lock(readers_mutex_);
    std::map<std::string, std::uint64_t> counts;
    for (const auto& [topic, reader] : readers_)
        counts[topic] = reader->received.load();
    return counts;
}

std::int32_t Recorder::matched_writers(const std::string& topic) const {
    std::lock_guard<std::mutex> lock(readers_mutex_);
    const auto it = readers_.find(topic);
    return it == readers_.end() ? 0 : it->second->matched.load();
}

}  // namespace tgw::basecamp
