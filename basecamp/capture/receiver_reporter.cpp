#include "basecamp/capture/receiver_reporter.hpp"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "ReceiverReportPubSubTypes.h"
#include "base/config_error.hpp"
#include "base/time.hpp"
#include "gateway/dds/receiver_report_topic.hpp"

namespace tgw::basecamp {

namespace fdds = eprosima::fastdds::dds;

ReceiverReporter::ReceiverReporter(fdds::DomainParticipant* participant) {
    fdds::TypeSupport type(new idl::ReceiverReportPubSubType());
    if (type.register_type(participant) != ReturnCode_t::RETCODE_OK)
        throw base::ConfigError("cannot register the receiver report type");
    fdds::Topic* topic =
        participant->create_topic(dds::RECEIVER_REPORT_TOPIC, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    fdds::Publisher* publisher = participant->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    if (topic == nullptr || publisher == nullptr)
        throw base::ConfigError(std::string("cannot create the topic ") + dds::RECEIVER_REPORT_TOPIC);
    fdds::DataWriterQos qos = publisher->get_default_datawriter_qos();
    // Reliable, so a camp tool's reliable reader (ROS 2's default) matches; the gateways' best-effort readers
    // match it too. Keep last 1 per gateway: counts are cumulative, only the newest matters.
    qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
    qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    qos.history().depth = 1;
    qos.data_sharing().off();
    writer_ = publisher->create_datawriter(topic, qos);
    if (writer_ == nullptr)
        throw base::ConfigError(std::string("cannot create the writer of ") + dds::RECEIVER_REPORT_TOPIC);
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
