#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include "sensor/link_counter_reader.hpp"

namespace tgw::sensor {

/// What a base-camp receiver last reported about this gateway, cumulative, in the check's terms.
struct ReceiverCounts {
    std::uint64_t received_wire_bytes = 0;  ///< what arrived, as the gateway's wire model counts it
    std::uint64_t lost_samples = 0;         ///< samples written to the WAN and never received
    std::uint64_t in_flight_bytes = 0;      ///< sent, neither received nor lost yet: queued on the way
};

using CounterSource = std::function<KernelCountersReading()>;
using ReceiverSource = std::function<std::optional<ReceiverCounts>()>;

/// The delivered-rate check's counter source with the receiver's reported losses added to the qdisc's drops
/// and its bytes in flight as a backlog (the larger of the two with a qdisc), so that the check also cuts when
/// samples queue or vanish past this host (a router's queue, the radio itself). With `kernel` empty the reports
/// stand alone: the received bytes stand for the interface's transmit counter, and before the first report the
/// source fails, naming the cause. With both, a missing report adds nothing.
CounterSource with_receiver_reports(CounterSource kernel, ReceiverSource reports);

}  // namespace tgw::sensor
