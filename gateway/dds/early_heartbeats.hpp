// A reliable writer's HEARTBEAT in the message of a fragment that does not end its sample. Pure bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tgw::dds {

/// Fast DDS 2.9 puts a reliable writer's piggy-backed HEARTBEAT in every fragment's message once the writer has
/// sent its heartbeat spacing since the last one, so the HEARTBEAT of a sample's first fragment announces the whole
/// sample while its other fragments are still in the link's queue. A reader that has the first fragment then asks at
/// once for all the others (NACK_FRAG), and the writer sends them again: on the testbed a 6,000-byte picture crossed
/// the link 1.8 times (robot mix, 80,000 bit/s, Cyclone's reliable reader). Without the HEARTBEAT the reader asks
/// only at the last fragment's, for what is really missing.
///
/// Writes into `out` the message without its HEARTBEAT submessages and returns true when the message carries a
/// DATA_FRAG whose fragments do not reach the end of its sample, and a HEARTBEAT. False, `out` untouched, otherwise:
/// also for a message that is not well formed or is protected by DDS Security (whole or by submessage), whose bytes
/// must stay as signed.
bool without_early_heartbeats(const std::uint8_t* message, std::size_t size, std::vector<std::uint8_t>& out);

}  // namespace tgw::dds
