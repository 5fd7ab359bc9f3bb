#include "gateway/apps/tm_robot_sim/paper_publisher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "PaperWorkloadPubSubTypes.h"
#include "base/config_error.hpp"
#include "gateway/apps/tm_robot_sim/publish_schedule.hpp"

namespace tgw::robot_sim {

namespace dds = eprosima::fastdds::dds;

namespace {

/// Long enough for an announcement or a sample to cross the robot's own host.
constexpr auto IN_FLIGHT = std::chrono::milliseconds(200);

eprosima::fastrtps::Duration_t to_dds_duration(base::Duration d) {
    const auto ns = d.count();
    return eprosima::fastrtps::Duration_t(static_cast<int32_t>(ns / 1'000'000'000),
                                          static_cast<uint32_t>(ns % 1'000'000'000));
}

}  // namespace

PaperPublisher::PaperPublisher(int domain, const std::vector<core::MessageStream>& streams,
                               const base::PeerTransport& transport, WriterDurability durability)
    : streams_(streams) {
    auto* factory = dds::DomainParticipantFactory::get_instance();
    dds::DomainParticipantQos pqos = factory->get_default_participant_qos();
    pqos.name("tm-robot-sim");
    base::apply_peer_transport(pqos, transport, domain);
    participant_ = factory->create_participant(domain, pqos);
    if (participant_ == nullptr)
        throw base::ConfigError("--domain: cannot create a DDS participant on domain " + std::to_string(domain));

    dds::TypeSupport type(new tgw::idl::PaperMessagePubSubType());
    if (type.register_type(participant_) != ReturnCode_t::RETCODE_OK)
        throw base::ConfigError("cannot register type tgw::idl::PaperMessage");
    publisher_ = participant_->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
    if (publisher_ == nullptr)
        throw base::ConfigError("cannot create a DDS publisher");

    for (const core::MessageStream& stream : streams_) {
        dds::Topic* topic = participant_->create_topic(stream.topic, type.get_type_name(), dds::TOPIC_QOS_DEFAULT);
        if (topic == nullptr)
            throw base::ConfigError("--workload: cannot create topic '" + stream.topic + "'");
        dds::DataWriterQos wqos = publisher_->get_default_datawriter_qos();
        wqos.reliability().kind = dds::RELIABLE_RELIABILITY_QOS;
        wqos.durability().kind = durability == WriterDurability::transient_local ? dds::TRANSIENT_LOCAL_DURABILITY_QOS
                                                                                 : dds::VOLATILE_DURABILITY_QOS;
        wqos.lifespan().duration = to_dds_duration(stream.ttl);
        // Keep what can still be alive within the TTL: the writer queues like the paper's control did,
        // and the Lifespan purges what has expired.
        const auto alive = static_cast<int32_t>(std::ceil(base::to_seconds(stream.ttl) * stream.rate_hz)) + 1;
        wqos.history().kind = dds::KEEP_LAST_HISTORY_QOS;
        wqos.history().depth = alive;
        wqos.resource_limits().max_samples = alive;
        wqos.resource_limits().max_instances = 1;
        wqos.resource_limits().max_samples_per_instance = alive;
        // Every sample goes through the transport, so a shaped link sees all of it.
        wqos.data_sharing().off();
        dds::DataWriter* writer = publisher_->create_datawriter(topic, wqos);
        if (writer == nullptr)
            throw base::ConfigError("cannot create a DDS writer for '" + stream.topic + "'");
        writers_.push_back(writer);
    }
}

PaperPublisher::~PaperPublisher() {
    if (participant_ != nullptr) {
        // A best-effort reader acknowledges nothing, so linger() does not wait for it, yet the last samples may
        // still be on their way: through shared memory, whose segment goes with the participant.
        std::this_thread::sleep_for(IN_FLIGHT);
        participant_->delete_contained_entities();
        dds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
    }
}

std::vector<StreamReport> PaperPublisher::run(base::Duration duration, const std::atomic<bool>& stop) {
    std::vector<StreamReport> reports;
    std::vector<double> rates;
    std::vector<tgw::idl::PaperMessage> messages(streams_.size());
    for (std::size_t i = 0; i < streams_.size(); ++i) {
        reports.push_back({streams_[i], 0, 0, 0, 0.0, core::paper_message_serialized_bytes(streams_[i].data_bytes)});
        rates.push_back(streams_[i].rate_hz);
        std::vector<uint8_t> data(streams_[i].data_bytes);
        for (std::size_t b = 0; b < data.size(); ++b)
            data[b] = static_cast<uint8_t>(b);
        messages[i].data(std::move(data));
    }

    const base::SteadyTime start = base::SteadyClock::now();
    const base::SteadyTime end = start + duration;
    PublishSchedule schedule(start, rates);
    for (;;) {
        const PublishSchedule::Due due = schedule.next();
        if (due.at >= end || stop.load())
            break;
        std::this_thread::sleep_until(due.at);
        if (stop.load())
            break;
        const base::SteadyTime now = base::SteadyClock::now();
        StreamReport& report = reports[due.stream];
        const double lag_ms = std::chrono::duration<double, std::milli>(now - due.at).count();
        report.max_lag_ms = std::max(report.max_lag_ms, lag_ms);
        if (lag_ms * streams_[due.stream].rate_hz > 1000.0)
            ++report.late;

        const std::int64_t wall_ns = base::to_ns(base::WallClock::now());
        tgw::idl::PaperMessage& message = messages[due.stream];
        message.generated_ns(static_cast<uint64_t>(wall_ns));
        message.sequence_number(due.sequence);
        const eprosima::fastrtps::Time_t stamp(static_cast<int32_t>(wall_ns / 1'000'000'000),
                                               static_cast<uint32_t>(wall_ns % 1'000'000'000));
        if (writers_[due.stream]->write_w_timestamp(&message, dds::HANDLE_NIL, stamp) == ReturnCode_t::RETCODE_OK)
            ++report.written;
        else
            ++report.failed;
        schedule.advance();
    }
    return reports;
}

std::size_t PaperPublisher::wait_for_readers(base::Duration max_wait) {
    const auto end = base::SteadyClock::now() + max_wait;
    for (;;) {
        std::size_t unmatched = 0;
        for (dds::DataWriter* writer : writers_) {
            dds::PublicationMatchedStatus status;
            writer->get_publication_matched_status(status);
            if (status.current_count == 0)
                ++unmatched;
        }
        if (unmatched == 0) {
            // Our writer matched the reader on its announcement; the reader matches our writer on ours, which
            // may be processed a moment later, and a best-effort reader drops what comes before.
            std::this_thread::sleep_for(IN_FLIGHT);
            return 0;
        }
        if (base::SteadyClock::now() >= end)
            return unmatched;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

void PaperPublisher::linger(base::Duration max_wait) {
    // Reliable samples still unacknowledged are lost when the participant goes; give them a bounded chance.
    const auto end = base::SteadyClock::now() + max_wait;
    for (dds::DataWriter* writer : writers_) {
        const auto left = std::max(base::Duration::zero(), end - base::SteadyClock::now());
        writer->wait_for_acknowledgments(to_dds_duration(left));
    }
}

void print_reports(std::ostream& out, const std::vector<StreamReport>& reports, double seconds) {
    char line[256];
    std::snprintf(line, sizeof(line), "%-5s %-16s %10s %7s %8s %8s %7s %6s %12s %12s\n", "type", "topic", "data_bytes",
                  "ttl_s", "written", "failed", "late", "lag_ms", "payload_B", "payload_bps");
    out << line;
    std::uint64_t written = 0;
    double bps_total = 0.0;
    for (const StreamReport& r : reports) {
        const double bps = seconds > 0 ? static_cast<double>(r.written * r.serialized_bytes * 8) / seconds : 0.0;
        std::snprintf(line, sizeof(line), "%-5s %-16s %10zu %7.1f %8llu %8llu %7llu %6.1f %12zu %12.0f\n",
                      r.stream.type.c_str(), r.stream.topic.c_str(), r.stream.data_bytes,
                      base::to_seconds(r.stream.ttl), static_cast<unsigned long long>(r.written),
                      static_cast<unsigned long long>(r.failed), static_cast<unsigned long long>(r.late), r.max_lag_ms,
                      r.serialized_bytes, bps);
        out << line;
        written += r.written;
        bps_total += bps;
    }
    std::snprintf(line, sizeof(line), "total: %llu samples in %.1f s, %.0f bit/s of serialized payload\n",
                  static_cast<unsigned long long>(written), seconds, bps_total);
    out << line;
}

}  // namespace tgw::robot_sim
