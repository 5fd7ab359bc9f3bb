#include "basecamp/capture/receiver_reporter.hpp"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "ReceiverReportPubSubTypes.h"
#include "base/config_error.hpp"
#include "base/time.hpp"
#include "basecamp/capture/latest_per_gateway_qos.hpp"
#include "wire/receiver_report_topic.hpp"

namespace tgw::basecamp {

namespace fdds = eprosima::fastdds::dds;

ReceiverReporter::ReceiverReporter(fdds::DomainParticipant* participant) {
    fdds::TypeSupport type(new idl::ReceiverReportPubSubType());
    if (type.register_type(participant) != ReturnCode_t::RETCODE_OK)
        throw base::ConfigError("cannot register the receiver report type");
    fdds::Topic* topic =
        participant->create_topic(wire::RECEIVER_REPORT_TOPIC, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    fdds::Publisher* publisher = participant->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    if (topic == nullptr || publisher == nullptr)
        throw base::ConfigError(std::string("cannot create the topic ") + wire::RECEIVER_REPORT_TOPIC);
    // Counts are cumulative: only the newest per gateway matters.
    writer_ = publisher->create_datawriter(topic, latest_per_gateway_qos(*publisher));
    if (writer_ == nullptr)
        throw base::ConfigError(std::string("cannot create the writer of ") + wire::RECEIVER_REPORT_TOPIC);
}

bool ReceiverReporter::publish(const std::map<ParticipantPrefix, DeliveryTotals>& totals) {
    bool ok = true;
    const auto now_ns = static_cast<std::uint64_t>(base::to_ns(base::WallClock::now()));
    for (const auto& [prefix, t] : totals) {
        idl::ReceiverReport report;
        report.gateway_prefix(prefix);
        report.received_samples(t.received_samples);
        report.received_bytes(t.received_bytes);
        report.lost_samples(t.lost_samples);
        report.sent_ns(now_ns);
        ok = writer_->write(&report) && ok;
    }
    return ok;
}

}  // namespace tgw::basecamp
