#include "gateway/dds/receiver_report_reader.hpp"

#include <algorithm>
#include <utility>

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "ReceiverReport.h"

namespace tgw::dds {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

ReceiverReportReader::ReceiverReportReader(const eprosima::fastrtps::rtps::GuidPrefix_t& own,
                                           std::function<std::uint64_t()> forwarded_samples)
    : own_(own), forwarded_samples_(std::move(forwarded_samples)) {}

void ReceiverReportReader::on_data_available(fdds::DataReader* reader) {
    idl::ReceiverReport report;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&report, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data ||
            !std::equal(report.gateway_prefix().begin(), report.gateway_prefix().end(), std::begin(own_.value))) {
            continue;
        }
        const std::uint64_t forwarded = forwarded_samples_();
        const eprosima::fastrtps::rtps::GUID_t receiver = info.sample_identity.writer_guid();
        std::lock_guard<std::mutex> lock(mutex_);
        if (!receiver_) {
            receiver_ = receiver;
        } else if (*receiver_ != receiver) {
            continue;
        }
        ReceiverReportTotals totals;
        totals.received_samples = report.received_samples();
        totals.received_bytes = report.received_bytes();
        totals.lost_samples = report.lost_samples();
        const std::uint64_t accounted = totals.received_samples + totals.lost_samples;
        const std::uint64_t raw = forwarded > accounted ? forwarded - accounted : 0;
        never_accounted_ = std::min(raw, never_accounted_.value_or(raw));
        totals.in_flight_samples = raw - *never_accounted_;
        totals.reports = latest_ ? latest_->reports + 1 : 1;
        latest_ = totals;
    }
}

std::optional<ReceiverReportTotals> ReceiverReportReader::latest() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return latest_;
}

}  // namespace tgw::dds
