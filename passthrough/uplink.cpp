#include "passthrough/uplink.hpp"

#include <atomic>
#include <iostream>
#include <utility>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include "passthrough/dds_time.hpp"
#include "passthrough/passthrough_qos.hpp"
#include "passthrough/passthrough_route.hpp"
#include "passthrough/passthrough_type.hpp"
#include "passthrough/uplink_topics.hpp"

namespace tgw::passthrough {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

/// One listed topic: a passthrough route of its fresh samples, stamped with their source time, counted and charged
/// to the link.
class Uplink::Route final : public PassthroughRoute {
  public:
    Route(UplinkCount names, bool keyed, const eprosima::fastrtps::rtps::GuidPrefix_t& own, const base::Clock& clock,
          const core::WireModel& wire, const Charge& charge)
        : PassthroughRoute(keyed), names_(std::move(names)), own_(own), clock_(clock), wire_(wire), charge_(charge) {}

    void on_subscription_matched(fdds::DataReader* /*reader*/, const fdds::SubscriptionMatchedStatus& info) override {
        writers_.store(info.current_count);
    }

    UplinkCount counts() const {
        UplinkCount out = names_;
        out.received = received_.load();
        out.delivered = delivered_.load();
        out.no_reader = no_reader_.load();
        out.expired = expired_.load();
        out.failed = failed_.load();
        out.wire_bytes = wire_bytes_.load();
        out.writers = writers_.load();
        out.readers = readers_matched();
        return out;
    }

  private:
    std::optional<eprosima::fastrtps::Time_t> admit(const PassthroughData& data,
                                                    const fdds::SampleInfo& info) override {
        if (info.sample_identity.writer_guid().guidPrefix == own_) {
            return std::nullopt;  // our own writer of a topic also bridged the other way
        }
        received_.fetch_add(1, std::memory_order_relaxed);
        const std::uint64_t wire_bytes = wire_.wire_bytes(data.payload.size());
        wire_bytes_.fetch_add(wire_bytes, std::memory_order_relaxed);
        if (charge_) {
            charge_(wire_bytes);
        }
        // A sample without a source timestamp is judged by its arrival: it cannot be older than that.
        const base::WallTime now = clock_.wall_now();
        const base::WallTime source = to_wall_time(info.source_timestamp).value_or(now);
        if (names_.ttl && uplink_expired(source, names_.ttl->ttl, now)) {
            expired_.fetch_add(1, std::memory_order_relaxed);
            return std::nullopt;
        }
        return to_dds_time(source);
    }

    void written(ReturnCode_t rc, bool reader_matched) override {
        if (rc == ReturnCode_t::RETCODE_OK) {
            (reader_matched ? delivered_ : no_reader_).fetch_add(1, std::memory_order_relaxed);
        } else if (failed_.fetch_add(1, std::memory_order_relaxed) == 0) {
            std::cerr << "uplink: a write on " << names_.to_topic << " failed (code " << rc() << ")\n";
        }
    }

    const UplinkCount names_;
    const eprosima::fastrtps::rtps::GuidPrefix_t own_;
    const base::Clock& clock_;
    const core::WireModel& wire_;
    const Charge& charge_;
    std::atomic<std::uint64_t> received_{0};
    std::atomic<std::uint64_t> delivered_{0};
    std::atomic<std::uint64_t> no_reader_{0};
    std::atomic<std::uint64_t> expired_{0};
    std::atomic<std::uint64_t> failed_{0};
    std::atomic<std::uint64_t> wire_bytes_{0};
    std::atomic<std::int32_t> writers_{0};
};

Uplink::Uplink(fdds::DomainParticipant* from, fdds::DomainParticipant* to, const base::Clock& clock,
               core::WireModel wire, Charge charge)
    : from_(from),
      to_(to),
      clock_(clock),
      wire_(std::move(wire)),
      charge_(std::move(charge)),
      own_(from->guid().guidPrefix) {}

Uplink::~Uplink() {
    close();
}

void Uplink::close() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) {
        return;
    }
    closed_ = true;
    for (const auto& [topic, route] : routes_) {
        closed_counts_.push_back(route->counts());
    }
    routes_.clear();  // each route's reader, then its writer
}

bool Uplink::route(const DiscoveredPublisher& publisher, const std::string& to_topic,
                   const std::optional<ResolvedTtl>& ttl) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) {
        return false;
    }
    if (routes_.count(publisher.topic) != 0) {
        return true;
    }
    fdds::Topic* from_topic = passthrough_topic(from_, publisher.topic, publisher.type_name, publisher.keyed);
    fdds::Topic* to_topic_entity =
        passthrough_topic(to_, to_topic, publisher.type_name, publisher.keyed, publisher.type_object);
    fdds::Subscriber* subscriber = subscribers_.get(from_, publisher.qos);
    fdds::Publisher* to_publisher = publishers_.get(to_, publisher.qos);
    if (from_topic == nullptr || to_topic_entity == nullptr || subscriber == nullptr || to_publisher == nullptr) {
        std::cerr << "uplink: cannot create the route of " << publisher.topic << " (type " << publisher.type_name
                  << ")\n";
        return false;
    }
    UplinkCount names;
    names.from_topic = publisher.topic;
    names.to_topic = to_topic;
    names.type_name = publisher.type_name;
    names.ttl = ttl;
    auto route = std::make_unique<Route>(std::move(names), publisher.keyed, own_, clock_, wire_, charge_);
    const std::optional<base::Duration> lifespan = ttl ? std::optional<base::Duration>(ttl->ttl) : std::nullopt;
    OfferedQos any_writer = publisher.qos;
    any_writer.reliable = false;  // best effort matches every writer, and asks the link for no repairs
    any_writer.transient_local = false;
    const bool routed = route->open_writer(*to_publisher, to_topic_entity,
                                           passthrough_writer_qos(to_publisher->get_default_datawriter_qos(),
                                                                  publisher.qos, publisher.keyed, lifespan)) &&
                        route->attach_reader(*subscriber, from_topic,
                                             passthrough_reader_qos(subscriber->get_default_datareader_qos(),
                                                                    any_writer, publisher.keyed));
    if (!routed) {
        std::cerr << "uplink: cannot create the route of " << publisher.topic << " (" << publisher.qos.describe()
                  << ")\n";
        return false;
    }
    routes_.emplace(publisher.topic, std::move(route));
    return true;
}

std::vector<UplinkCount> Uplink::counts() const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) {
        return closed_counts_;
    }
    std::vector<UplinkCount> out;
    for (const auto& [topic, route] : routes_) {
        out.push_back(route->counts());
    }
    return out;
}

}  // namespace tgw::passthrough
