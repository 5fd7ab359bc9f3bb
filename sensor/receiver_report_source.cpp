#include "sensor/receiver_report_source.hpp"

#include <algorithm>
#include <utility>

namespace tgw::sensor {

CounterSource with_receiver_reports(CounterSource kernel, ReceiverSource reports) {
    return [kernel = std::move(kernel), reports = std::move(reports)] {
        const std::optional<ReceiverCounts> report = reports();
        if (kernel) {
            KernelCountersReading reading = kernel();
            if (reading.ok && report) {
                reading.counters.drops += report->lost_samples;
                reading.counters.backlog_bytes = std::max(reading.counters.backlog_bytes, report->in_flight_bytes);
            }
            return reading;
        }
        KernelCountersReading reading;
        if (!report) {
            reading.error = "no receiver report yet (is tm-basecamp record running with --report-period?)";
            return reading;
        }
        reading.ok = true;
        reading.counters.tx_bytes = report->received_wire_bytes;
        reading.counters.drops = report->lost_samples;
        reading.counters.backlog_bytes = report->in_flight_bytes;
        return reading;
    };
}

}  // namespace tgw::sensor
