// A reliable reader's repair, held for the schedule like the sample it repairs.
#pragma once

#include <cstdint>

#include "base/time.hpp"
#include "gateway/core/sample.hpp"

namespace tgw::core {

/// What the WAN participant would send again for a reliable reader (a lost sample or some of its fragments, or
/// a late joiner's history). It belongs to the sample it repairs: that sample's topic gives its urgency and that
/// sample's deadline its own, so it waits behind more urgent samples, is charged when it leaves, and is never sent
/// once it cannot arrive in time. Its bytes stay with whoever made it, under `id`.
struct Repair {
    std::uint64_t id = 0;
    TopicId topic = 0;
    base::SteadyTime deadline{};
    std::uint64_t wire_bits = 0;  ///< what it puts on the link, headers included
};

/// What became of the repairs the scheduler was given.
struct RepairCounters {
    std::uint64_t received = 0;
    std::uint64_t sent = 0;
    std::uint64_t sent_wire_bytes = 0;
    /// Not sent: they could no longer arrive before the repaired sample's deadline.
    std::uint64_t late = 0;
    /// Not sent: the queue of repairs was full, or the gateway stopped.
    std::uint64_t discarded = 0;
    std::uint64_t queued = 0;  ///< waiting now
};

}  // namespace tgw::core
