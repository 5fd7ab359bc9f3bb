#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>

#include <fastdds/rtps/common/Guid.h>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>

#include "base/time.hpp"

namespace tgw::dds {

/// A base-camp receiver's last report about this gateway (idl/ReceiverReport.idl): cumulative counts.
struct ReceiverReportTotals {
    std::uint64_t received_samples = 0;
    std::uint64_t received_bytes = 0;  ///< serialized payload bytes
    std::uint64_t lost_samples = 0;
    /// Forwarded when the report came and neither received nor lost: queued somewhere on the way. The report
    /// crosses the other direction, which is not the congested one, so it comes within milliseconds. Counted
    /// above the smallest such figure seen: what went out before the receiver's readers matched is never
    /// received nor counted lost, and would otherwise stay in flight for ever.
    std::uint64_t in_flight_samples = 0;
    std::uint64_t reports = 0;  ///< reports taken so far from the followed receiver
};

/// Listens on dds::RECEIVER_REPORT_TOPIC and keeps the latest report about `own` (the gateway's WAN participant)
/// from one receiver: the first one heard, because cumulative counts of two receivers cannot be mixed.
/// Reports about other gateways and from other receivers are ignored. Thread-safe.
class ReceiverReportReader final : public eprosima::fastdds::dds::DataReaderListener {
  public:
    /// `forwarded_samples`: the gateway's cumulative forwarded count, read as each report arrives.
    ReceiverReportReader(const eprosima::fastrtps::rtps::GuidPrefix_t& own,
                         std::function<std::uint64_t()> forwarded_samples);

    void on_data_available(eprosima::fastdds::dds::DataReader* reader) override;

    /// The latest report, or nullopt before the first.
    std::optional<ReceiverReportTotals> latest() const;

  private:
    eprosima::fastrtps::rtps::GuidPrefix_t own_;
    std::function<std::uint64_t()> forwarded_samples_;
    mutable std::mutex mutex_;
    std::optional<eprosima::fastrtps::rtps::GUID_t> receiver_;  ///< guarded by mutex_
    std::optional<ReceiverReportTotals> latest_;                ///< guarded by mutex_
    std::optional<std::uint64_t> never_accounted_;              ///< guarded by mutex_: the smallest raw in-flight
};

}  // namespace tgw::dds
