#include "basecamp/capture/backfill_endpoints.hpp"

#include <cstdio>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "base/config_error.hpp"
#include "base/time.hpp"
#include "passthrough/guarded_type.hpp"
#include "passthrough/take_each.hpp"
#include "wire/backfill_topics.hpp"

namespace tgw::basecamp {

namespace fdds = eprosima::fastdds::dds;

namespace {

fdds::Topic* make_topic(fdds::DomainParticipant* participant, const char* name, fdds::TypeSupport type) {
    if (type.register_type(participant) != ReturnCode_t::RETCODE_OK)
        throw base::ConfigError(std::string("cannot register the type of ") + name);
    fdds::Topic* topic = participant->create_topic(name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    if (topic == nullptr)
        throw base::ConfigError(std::string("cannot create the topic ") + name);
    return topic;
}

}  // namespace

BackfillEndpoints::BackfillEndpoints(fdds::DomainParticipant* wan, BackfillArchive& archive) : archive_(archive) {
    fdds::Topic* acks = make_topic(wan, wire::BACKFILL_ACK_TOPIC,
                                   fdds::TypeSupport(new passthrough::GuardedType<idl::BackfillAckPubSubType>()));
    fdds::Publisher* publisher = wan->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    if (publisher == nullptr)
        throw base::ConfigError(std::string("cannot create a publisher for ") + wire::BACKFILL_ACK_TOPIC);
    fdds::DataWriterQos writer_qos = publisher->get_default_datawriter_qos();
    // Reliable: an acknowledgement tells only what is new since the last, and the robot frees nothing without one.
    // A few kept per log, as the gateway's reader keeps them.
    writer_qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    writer_qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
    writer_qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    writer_qos.history().depth = 16;
    writer_qos.data_sharing().off();
    writer_ = publisher->create_datawriter(acks, writer_qos);
    if (writer_ == nullptr)
        throw base::ConfigError(std::string("cannot create the writer of ") + wire::BACKFILL_ACK_TOPIC);

    fdds::Topic* samples = make_topic(wan, wire::BACKFILL_TOPIC,
                                      fdds::TypeSupport(new passthrough::GuardedType<idl::BackfillSamplePubSubType>()));
    fdds::Subscriber* subscriber = wan->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    if (subscriber == nullptr)
        throw base::ConfigError(std::string("cannot create a subscriber for ") + wire::BACKFILL_TOPIC);
    fdds::DataReaderQos reader_qos = subscriber->get_default_datareader_qos();
    reader_qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
    reader_qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
    reader_qos.history().kind = fdds::KEEP_ALL_HISTORY_QOS;
    reader_qos.data_sharing().off();
    reader_ = subscriber->create_datareader(samples, reader_qos, this);
    if (reader_ == nullptr)
        throw base::ConfigError(std::string("cannot create the reader of ") + wire::BACKFILL_TOPIC);
}

std::unique_ptr<BackfillEndpoints> BackfillEndpoints::make_or_say_why(fdds::DomainParticipant* wan,
                                                                      BackfillArchive& archive) {
    try {
        return std::make_unique<BackfillEndpoints>(wan, archive);
    } catch (const base::ConfigError& error) {
        std::fprintf(stderr,
                     "tm-basecamp: %s: the gateways' backfill is not archived (with DDS Security, the camp's "
                     "permissions must allow publishing %s)\n",
                     error.what(), wire::BACKFILL_ACK_TOPIC);
        return nullptr;
    }
}

BackfillEndpoints::~BackfillEndpoints() {
    if (reader_ != nullptr)
        reader_->set_listener(nullptr);
}

void BackfillEndpoints::on_data_available(fdds::DataReader* reader) {
    passthrough::take_valid<idl::BackfillSample>(
        *reader, [this](const idl::BackfillSample& sample, const fdds::SampleInfo& /*info*/) {
            archive_.take(sample, base::to_ns(base::WallClock::now()));
        });
}

void BackfillEndpoints::publish_acks_when_due() {
    const auto now = std::chrono::steady_clock::now();
    if (now < next_acks_)
        return;
    next_acks_ = now + ACK_PERIOD;
    for (idl::BackfillAck& ack : archive_.take_acks(static_cast<std::uint64_t>(base::to_ns(base::WallClock::now()))))
        writer_->write(&ack);
}

}  // namespace tgw::basecamp
