#pragma once

namespace tgw::wire {

/// The WAN topic on which base-camp receivers tell each gateway what arrived (idl/ReceiverReport.idl): the one
/// topic that goes from the base camp to the robot, read by the gateway itself and never bridged.
inline constexpr const char* RECEIVER_REPORT_TOPIC = "tgw/receiver_report";

}  // namespace tgw::wire
