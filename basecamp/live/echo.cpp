#include "basecamp/live/echo.hpp"

#include <cstdio>
#include <sstream>

#include <fastrtps/types/TypeObjectFactory.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include "base/config_error.hpp"
#include "basecamp/capture/camp_participant.hpp"
#include "passthrough/dds_time.hpp"
#include "passthrough/passthrough_qos.hpp"
#include "passthrough/passthrough_type.hpp"
#include "passthrough/take_each.hpp"
#include "passthrough/type_object_idl.hpp"

namespace tgw::basecamp {

namespace fdds = eprosima::fastdds::dds;

namespace {

constexpr std::size_t KEY_HASH_BYTES = 16;

}  // namespace

/// The reader of one QoS offer of the topic; its listener queues each sample of the writers assigned to it.
class Echo::Lane final : public fdds::DataReaderListener {
  public:
    Lane(Echo& echo, std::uint16_t index) : echo_(echo), index_(index) {}

    ~Lane() override {
        if (reader != nullptr) {
            reader->set_listener(nullptr);
            const_cast<fdds::Subscriber*>(reader->get_subscriber())->delete_datareader(reader);
        }
    }

    void on_data_available(fdds::DataReader* from) override {
        // Disposes and unregisters carry no sample to print.
        passthrough::take_valid<passthrough::PassthroughData>(
            *from, [this](passthrough::PassthroughData& data, const fdds::SampleInfo& info) {
                if (!echo_.writers_.carries(info.publication_handle, index_))
                    return;
                ReceivedSample sample;
                sample.payload = std::move(data.payload);
                sample.source = passthrough::to_wall_time(info.source_timestamp);
                if (echo_.keyed_ && info.instance_handle == passthrough::PassthroughType::UNKNOWN_INSTANCE) {
                    sample.instance = "unknown (the writer sent no key hash)";
                } else if (echo_.keyed_ && info.instance_handle.isDefined()) {
                    // The handle's value holds a flag after the 16 bytes of the key hash.
                    std::uint8_t key_hash[KEY_HASH_BYTES];
                    for (std::size_t i = 0; i < KEY_HASH_BYTES; ++i)
                        key_hash[i] = info.instance_handle.value[i];
                    sample.instance = hex_text(key_hash, KEY_HASH_BYTES);
                }
                echo_.push(std::move(sample));
            });
    }

    fdds::DataReader* reader = nullptr;
    passthrough::OfferedQos offer;

  private:
    Echo& echo_;
    const std::uint16_t index_;
};

Echo::Echo(int domain, const base::PeerTransport& transport, std::string topic, types::TypeLibrary types,
           SamplePrinter::Format format, std::ostream& out, const std::optional<base::SecurityFiles>& security)
    : topic_(std::move(topic)), types_(std::move(types)), format_(format), out_(out) {
    discovery_ = std::make_unique<passthrough::Discovery>(discovered_.callback());
    participant_ = create_camp_participant(domain, transport, security, "tm-basecamp echo", *discovery_);
}

Echo::~Echo() {
    if (participant_ == nullptr)
        return;
    participant_->set_listener(nullptr);
    lanes_.clear();  // each reader before the participant goes
    participant_->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

std::string Echo::type_name() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return type_name_;
}

void Echo::subscribe(const passthrough::DiscoveredPublisher& publisher) {
    if (publisher.topic != topic_)
        return;
    if (!printer_) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            type_name_ = publisher.type_name;
        }
        keyed_ = publisher.keyed;
        const std::string how = learn_announced_type(publisher);
        printer_.emplace(types_, type_name_, format_);
        std::fprintf(stderr, "tm-basecamp echo: '%s' of type %s%s\n", topic_.c_str(), type_name_.c_str(), how.c_str());
    } else if (publisher.type_name != type_name_) {
        std::fprintf(stderr, "tm-basecamp echo: ignoring a publisher of '%s' with another type (%s, not %s)\n",
                     topic_.c_str(), publisher.type_name.c_str(), type_name_.c_str());
        return;
    }
    for (std::size_t i = 0; i < lanes_.size(); ++i) {
        if (lanes_[i]->offer == publisher.qos) {
            writers_.assign(publisher.writer, static_cast<std::uint16_t>(i));
            return;
        }
    }
    const auto index = static_cast<std::uint16_t>(lanes_.size());
    fdds::Topic* topic = passthrough::passthrough_topic(participant_, topic_, type_name_, keyed_);
    fdds::Subscriber* subscriber = subscribers_.get(participant_, publisher.qos);
    auto lane = std::make_unique<Lane>(*this, index);
    lane->offer = publisher.qos;
    if (topic != nullptr && subscriber != nullptr) {
        lane->reader = subscriber->create_datareader(
            topic, passthrough::passthrough_reader_qos(subscriber->get_default_datareader_qos(), publisher.qos, keyed_),
            lane.get(), fdds::StatusMask::data_available());
    }
    if (lane->reader == nullptr) {
        std::fprintf(stderr, "tm-basecamp echo: cannot subscribe to '%s' (%s)\n", topic_.c_str(),
                     publisher.qos.describe().c_str());
        return;
    }
    writers_.assign(publisher.writer, index);
    lanes_.push_back(std::move(lane));
}

std::string Echo::learn_announced_type(const passthrough::DiscoveredPublisher& publisher) {
    if (types_.find(publisher.type_name) != nullptr)
        return "";
    const std::string no_idl = "no IDL for it, samples print as size and hex (--idl DIR adds IDL files)";
    if (!publisher.type_object)
        return ": " + no_idl;
    // Types it refers to by hash: only those this process has registered. Fast DDS 2.9 asks a publisher for them
    // (TypeLookup) only where the publisher serves it, which is off by default.
    const passthrough::TypeObjectIdl announced = passthrough::type_object_idl(
        *publisher.type_object, publisher.type_name, [](const eprosima::fastrtps::types::TypeIdentifier& id) {
            return eprosima::fastrtps::types::TypeObjectFactory::get_instance()->get_type_object(&id);
        });
    if (!announced.ok())
        return ": its publisher's TypeObject: " + announced.missing + "; " + no_idl;
    const std::string source = "the TypeObject of " + publisher.type_name;
    try {
        std::istringstream idl(announced.text);
        types::TypeLibrary with_announced = types_;
        with_announced.add_idl(idl, source);
        with_announced.check_references();
        types_ = std::move(with_announced);
    } catch (const base::ConfigError& e) {
        return ": its publisher's TypeObject does not make IDL this decoder reads (" + std::string(e.what()) + "); " +
               no_idl;
    }
    return ", decoded with the XTypes TypeObject its publisher announced";
}

void Echo::push(ReceivedSample&& sample) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        queued_.push_back(std::move(sample));
    }
    arrived_.notify_all();
}

std::vector<ReceivedSample> Echo::take(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    arrived_.wait_for(lock, timeout, [this] { return !queued_.empty(); });
    std::vector<ReceivedSample> out(std::make_move_iterator(queued_.begin()), std::make_move_iterator(queued_.end()));
    queued_.clear();
    return out;
}

std::uint64_t Echo::run(std::uint64_t count, base::Duration duration, const std::atomic<bool>& stop) {
    using std::chrono::milliseconds;
    const auto end = base::SteadyClock::now() + duration;
    std::uint64_t printed = 0;
    while (!stop.load() && base::SteadyClock::now() < end && (count == 0 || printed < count)) {
        // Before the first publisher, wait on discovery; after it, on samples.
        for (const passthrough::DiscoveredPublisher& publisher :
             discovered_.take(milliseconds(lanes_.empty() ? 100 : 0)))
            subscribe(publisher);
        for (const ReceivedSample& sample : take(milliseconds(lanes_.empty() ? 0 : 100))) {
            if (count != 0 && printed == count)
                break;  // the rest arrived together with the last one asked for
            printer_->print(out_, sample);
            out_.flush();  // a pipe (jq, a test) sees each sample as it comes
            ++printed;
        }
    }
    return printed;
}

}  // namespace tgw::basecamp
