#include "gateway/dds/receiver_report_reader.hpp"

#include <algorithm>
#include <iterator>
#include <utility>

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "ReceiverReport.h"
#include "passthrough/take_each.hpp"

namespace tgw::dds {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

ReceiverReportReader::ReceiverReportReader(const eprosima::fastrtps::rtps::GuidPrefix_t& own,
                                           std::function<std::uint64_t()> forwarded_samples, const base::Clock& clock)
    : forwarded_samples_(std::move(forwarded_samples)), own_(own), ledger_(clock, RECEIVER_SILENCE) {}

void ReceiverReportReader::set_own(const eprosima::fastrtps::rtps::GuidPrefix_t& own) {
    std::lock_guard<std::mutex> lock(mutex_);
    own_ = own;
    ledger_.reset();
}

void ReceiverReportReader::on_data_available(fdds::DataReader* reader) {
    // Held throughout, forwarded_samples_ included: close() waits for a report being taken.
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) {
        return;
    }
    passthrough::take_valid<idl::ReceiverReport>(
        *reader, [this](const idl::ReceiverReport& report, const fdds::SampleInfo& info) {
            if (!std::equal(report.gateway_prefix().begin(), report.gateway_prefix().end(), std::begin(own_.value))) {
                return;  // another gateway's
            }
            const eprosima::fastrtps::rtps::GUID_t& writer = info.sample_identity.writer_guid();
            sensor::ReceiverId from{};
            std::copy(std::begin(writer.guidPrefix.value), std::end(writer.guidPrefix.value), from.begin());
            std::copy(std::begin(writer.entityId.value), std::end(writer.entityId.value), from.begin() + 12);
            ledger_.take(from, {report.received_samples(), report.received_bytes(), report.lost_samples()},
                         forwarded_samples_());
        });
}

void ReceiverReportReader::close() {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
}

std::optional<ReceiverReportTotals> ReceiverReportReader::latest() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return ledger_.latest();
}

}  // namespace tgw::dds
