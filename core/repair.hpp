// A reliable reader's repair, held for the schedule like the sample it repairs.
#pragma once

#include <cstddef>
#include <cstdint>

#include "base/time.hpp"
#include "core/sample.hpp"

namespace tgw::core {

/// Bytes the WAN participant would send outside the scheduler's own writes, held so that the schedule sends them.
/// Most are repairs: what it would send again for a reliable reader (a lost sample or some of its fragments, or a
/// late joiner's history). Each belongs to the sample it carries: that sample's topic gives its urgency and that
/// sample's deadline its own, so it waits behind more urgent samples, is charged when it leaves, and is never sent
/// once it cannot arrive in time. Its bytes stay with whoever made it, under `id`.
struct Repair {
    enum class Kind {
        repair,
        /// One copy of the WAN participant's own announcement (SPDP), held so that nothing periodic steals a
        /// deadline. It has no topic: it ranks as a sample of ANNOUNCEMENT_TTL, and at its deadline
        /// (ANNOUNCEMENT_WAIT after it was made, its copies 250 ms apart) it is sent all the same, never discarded:
        /// the base camp drops a participant that stops announcing itself.
        announcement,
        /// One copy of a WAN writer's announcement (its SEDP DATA(w)): a base camp matches the writer, and takes its
        /// samples, only once it has it. It ranks as its topic's samples, so that a hazard's writer is announced
        /// before a picture's and a hazard's first sample goes before the picture's writer is announced. At its
        /// deadline it is sent all the same, never discarded.
        writer_announcement,
        /// A fragment after the first of a sample a scheduled write has just sent (standard mode, a sample larger
        /// than a datagram). The write charged the whole sample: the scheduler gives `prepaid_bits` back when it
        /// takes the fragment and charges it as it leaves, one fragment at a time in the sample's urgency. A more
        /// urgent sample goes between two fragments, and a rate that falls finds one fragment in the link's queue,
        /// not a whole picture.
        continuation,
    };

    std::uint64_t id = 0;
    TopicId topic = 0;
    base::SteadyTime deadline{};
    std::uint64_t wire_bits = 0;  ///< what it puts on the link, headers included
    Kind kind = Kind::repair;
    std::uint64_t prepaid_bits = 0;  ///< a continuation's share of what its write charged
    /// A continuation's sample: the same number for all its fragments, never 0. Once one of them is not sent, the
    /// sample cannot arrive: the others are not sent either, and the sample counts as dropped, not forwarded.
    std::uint64_t sample = 0;
    std::size_t sample_payload_bytes = 0;  ///< a continuation's sample's
    /// An announcement that, at its deadline, is left out rather than sent when it would hold the link longer than
    /// the non-preemptive rule allows (a dip to 4,000 bit/s, where a copy is a second of the link). The base camp
    /// renews the participant's lease with every message it gets from it, and the next announcement comes 20 s
    /// later; the RepairDesk leaves out at most MAX_SKIPPED_ANNOUNCEMENTS in a row to one port.
    bool skippable = false;
};

/// The urgency of the WAN participant's announcements: behind the hazards and the state a robot sends, before its
/// bulk.
inline constexpr base::Duration ANNOUNCEMENT_TTL = std::chrono::seconds(5);
/// How long an announcement may wait for the link (announced every 20 s, and a lease of 120 s).
inline constexpr base::Duration ANNOUNCEMENT_WAIT = std::chrono::seconds(2);
/// Announcements to one port left out in a row at most (Repair::skippable): 60 s without one, half the lease.
inline constexpr int MAX_SKIPPED_ANNOUNCEMENTS = 2;

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
    /// The participant's announcements (Repair::Kind::announcement), apart from the above.
    std::uint64_t announcements_sent = 0;
    std::uint64_t announcements_sent_wire_bytes = 0;
    std::uint64_t announcements_late = 0;     ///< of those sent: at the end of their wait, whatever the budget
    std::uint64_t announcements_skipped = 0;  ///< left out at the end of their wait (Repair::skippable)
    /// WAN writers' announcements (Repair::Kind::writer_announcement), apart from the above.
    std::uint64_t writer_announcements_sent = 0;
    std::uint64_t writer_announcements_sent_wire_bytes = 0;
    std::uint64_t writer_announcements_late = 0;  ///< of those sent: at the end of their wait, whatever the budget
    /// Fragments paced after their sample's first (Repair::Kind::continuation), apart from the above.
    std::uint64_t continuations_received = 0;
    std::uint64_t continuations_sent = 0;
    std::uint64_t continuations_sent_wire_bytes = 0;
    /// Not sent: their sample could no longer arrive in time, or the gateway stopped.
    std::uint64_t continuations_late = 0;
    /// Samples whose fragments were not all sent (the above): counted dropped, not forwarded, and logged.
    std::uint64_t samples_cut_short = 0;
};

/// The highest rate at which a sample's fragments are paced (Repair::Kind::continuation): above it a fragment of
/// a full datagram is on the link for less than 1.2 ms, less than pacing it through the scheduler costs.
inline constexpr double CONTINUATION_PACING_MAX_BPS = 10e6;
/// Whether a large sample's fragments after its first wait for the schedule at `rate_bps` (the WAN transport's
/// RepairDesk and the scheduler's non-preemptive rule ask the same).
inline bool paces_fragments_at(double rate_bps) {
    return rate_bps > 0.0 && rate_bps <= CONTINUATION_PACING_MAX_BPS;
}

}  // namespace tgw::core
