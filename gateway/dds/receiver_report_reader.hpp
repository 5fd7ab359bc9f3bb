#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>

#include <fastdds/rtps/common/Guid.h>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>

#include "base/clock.hpp"
#include "sensor/receiver_report_ledger.hpp"

namespace tgw::dds {

using sensor::ReceiverReportTotals;

/// Listens on wire::RECEIVER_REPORT_TOPIC and keeps the reports about `own` (the gateway's WAN participant) in a
/// sensor::ReceiverReportLedger: one receiver at a time, a silent one given up after RECEIVER_SILENCE. Reports
/// about other gateways are ignored. Thread-safe.
class ReceiverReportReader final : public eprosima::fastdds::dds::DataReaderListener {
  public:
    /// Five report periods of tm-basecamp record's default: a restarted base camp is followed within seconds.
    static constexpr base::Duration RECEIVER_SILENCE = std::chrono::seconds(5);

    /// `forwarded_samples`: the gateway's cumulative forwarded count, read as each report arrives. `clock` must
    /// outlive the reader.
    ReceiverReportReader(const eprosima::fastrtps::rtps::GuidPrefix_t& own,
                         std::function<std::uint64_t()> forwarded_samples, const base::Clock& clock);

    void on_data_available(eprosima::fastdds::dds::DataReader* reader) override;

    /// The followed receiver's latest report; nullopt before the first and while no receiver reports.
    std::optional<ReceiverReportTotals> latest() const;

    /// The gateway's WAN participant was made anew (WanRouter::rebind): reports about `own` count from here, with
    /// no receiver followed yet.
    void set_own(const eprosima::fastrtps::rtps::GuidPrefix_t& own);

    /// Takes no further report: once it returns, `forwarded_samples` is neither running nor called again, so
    /// what it reads may go while the reader still exists.
    void close();

  private:
    std::function<std::uint64_t()> forwarded_samples_;
    mutable std::mutex mutex_;
    eprosima::fastrtps::rtps::GuidPrefix_t own_;  ///< guarded by mutex_
    sensor::ReceiverReportLedger ledger_;         ///< guarded by mutex_
    bool closed_ = false;                         ///< guarded by mutex_
};

}  // namespace tgw::dds
