#include "sensor/receiver_report_ledger.hpp"

#include <algorithm>
#include <limits>

namespace tgw::sensor {

namespace {

constexpr std::uint64_t MAX = std::numeric_limits<std::uint64_t>::max();

std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b) {
    return a > MAX - b ? MAX : a + b;
}

std::uint64_t saturating_mul(std::uint64_t a, std::uint64_t b) {
    return b != 0 && a > MAX / b ? MAX : a * b;
}

}  // namespace

ReceiverReportLedger::ReceiverReportLedger(const base::Clock& clock, base::Duration silence)
    : clock_(clock), silence_(silence) {}

bool ReceiverReportLedger::silent() const {
    return clock_.now() - last_report_ >= silence_;
}

void ReceiverReportLedger::reset() {
    receiver_.reset();
    last_report_ = {};
    latest_.reset();
    never_accounted_.reset();
}

bool ReceiverReportLedger::take(const ReceiverId& from, const ReceiverReportCounts& counts,
                                std::uint64_t forwarded_samples) {
    if (!receiver_ || (*receiver_ != from && silent())) {
        receiver_ = from;
        latest_.reset();
        never_accounted_.reset();
    } else if (*receiver_ != from) {
        return false;
    }
    last_report_ = clock_.now();

    ReceiverReportTotals totals;
    totals.received_samples = counts.received_samples;
    totals.received_bytes = counts.received_bytes;
    totals.lost_samples = counts.lost_samples;
    const std::uint64_t accounted = saturating_add(counts.received_samples, counts.lost_samples);
    const std::uint64_t raw = forwarded_samples > accounted ? forwarded_samples - accounted : 0;
    never_accounted_ = std::min(raw, never_accounted_.value_or(raw));
    totals.in_flight_samples = raw - *never_accounted_;
    totals.reports = latest_ ? latest_->reports + 1 : 1;
    latest_ = totals;
    return true;
}

std::optional<ReceiverReportTotals> ReceiverReportLedger::latest() const {
    if (!latest_ || silent()) {
        return std::nullopt;
    }
    return latest_;
}

ReceiverCounts receiver_counts(const ReceiverReportTotals& totals, std::uint64_t per_sample_wire_bytes,
                               std::uint64_t mean_wire_bytes) {
    ReceiverCounts counts;
    counts.received_wire_bytes =
        saturating_add(totals.received_bytes, saturating_mul(totals.received_samples, per_sample_wire_bytes));
    counts.lost_samples = totals.lost_samples;
    counts.in_flight_bytes = saturating_mul(totals.in_flight_samples, mean_wire_bytes);
    return counts;
}

}  // namespace tgw::sensor
