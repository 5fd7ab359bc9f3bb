#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "base/clock.hpp"
#include "sensor/receiver_report_source.hpp"

namespace tgw::sensor {

/// One report's cumulative counts, as a base-camp receiver wrote them (idl/ReceiverReport.idl). They come off
/// the network: any value is possible.
struct ReceiverReportCounts {
    std::uint64_t received_samples = 0;
    std::uint64_t received_bytes = 0;  ///< serialized payload bytes
    std::uint64_t lost_samples = 0;
};

/// A base-camp receiver's last report about this gateway, as the gateway keeps it.
struct ReceiverReportTotals {
    std::uint64_t received_samples = 0;
    std::uint64_t received_bytes = 0;  ///< serialized payload bytes
    std::uint64_t lost_samples = 0;
    /// Forwarded when the report came and neither received nor lost: queued somewhere on the way. The report
    /// crosses the other direction, which is not the congested one, so it comes within milliseconds. Counted
    /// above the smallest such figure seen from this receiver: what went out before its readers matched is never
    /// received nor counted lost, and would otherwise stay in flight for ever.
    std::uint64_t in_flight_samples = 0;
    std::uint64_t reports = 0;  ///< reports taken so far from the followed receiver
};

/// Who wrote a report: the GUID of the receiver's writer.
using ReceiverId = std::array<std::uint8_t, 16>;

/// The reports of one receiver at a time: the first one heard, because the cumulative counts of two receivers
/// cannot be mixed. A receiver silent for `silence` is given up (a base camp that restarted comes back as a new
/// participant whose counts start from zero) and the next one heard is followed. Counts saturate rather than
/// wrap. Pure logic on the injected clock; not thread-safe.
class ReceiverReportLedger {
  public:
    /// `clock` must outlive the ledger.
    ReceiverReportLedger(const base::Clock& clock, base::Duration silence);

    /// Takes a report from `from` at clock.now(); `forwarded_samples` is the gateway's cumulative forwarded
    /// count then. Returns false when the report is another receiver's than the one followed.
    bool take(const ReceiverId& from, const ReceiverReportCounts& counts, std::uint64_t forwarded_samples);

    /// The followed receiver's latest totals; nullopt before its first report and once it has been silent for
    /// `silence`.
    std::optional<ReceiverReportTotals> latest() const;

    /// Follows no receiver any more, as when made (the gateway's WAN participant was made anew).
    void reset();

  private:
    bool silent() const;

    const base::Clock& clock_;
    base::Duration silence_;
    std::optional<ReceiverId> receiver_;
    base::SteadyTime last_report_{};
    std::optional<ReceiverReportTotals> latest_;
    std::optional<std::uint64_t> never_accounted_;  ///< the smallest raw in-flight figure of this receiver
};

/// `totals` in the delivered-rate check's terms: received bytes on the wire as if each sample (each bundle in
/// compact mode) went in a datagram of its own, `per_sample_wire_bytes` of headers each; what is in flight at
/// `mean_wire_bytes` a sample. Saturates rather than wraps.
ReceiverCounts receiver_counts(const ReceiverReportTotals& totals, std::uint64_t per_sample_wire_bytes,
                               std::uint64_t mean_wire_bytes);

}  // namespace tgw::sensor
