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
    /// Not a repair: one copy of the WAN participant's own announcement (SPDP), held the same way so that nothing
    /// periodic steals a deadline. It has no topic: it ranks as a sample of ANNOUNCEMENT_TTL, and at its deadline
    /// (ANNOUNCEMENT_WAIT after it was made, its copies 250 ms apart) it is sent all the same, never discarded: the
    /// base camp drops a participant that stops announcing itself.
    bool announcement = false;
};

/// The urgency of the WAN participant's announcements: behind the hazards and the state a robot sends, before its
/// bulk.
inline constexpr base::Duration ANNOUNCEMENT_TTL = std::chrono::seconds(5);
/// How long an announcement may wait for the link (announced every 20 s, and a lease of 120 s).
inline constexpr base::Duration ANNOUNCEMENT_WAIT = std::chrono::seconds(2);

/// What became of the repairs the scheduler was given.
struct RepairCounters {
    std::uint64_t received = 0;
    std::uint64_t sent = 0;
    std::uint64_t sent_wire_bytes = 0;
    /// Not sent: they could no longer arrive before the repaired sample's deadline.
    std::uint64_t late = 0;
    /// Not sent: the queue of repairs was full, or the gateway stopped.
    std::uint64_t discarded = 0;
    std::uint64_t queued = 0;  ///< waiting now, announcements included
    /// The participant's announcements (Repair::announcement), apart from the above.
    std::uint64_t announcements_sent = 0;
    std::uint64_t announcements_sent_wire_bytes = 0;
    std::uint64_t announcements_late = 0;  ///< of those sent: at the end of their wait, whatever the budget
};

}  // namespace tgw::core
