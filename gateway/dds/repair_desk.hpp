// Holds the WAN participant's repairs for reliable readers, so that the schedule sends them (core::Repair).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "base/clock.hpp"
#include "core/repair.hpp"
#include "gateway/dds/datagram_coalescer.hpp"
#include "gateway/dds/rtps_sample_refs.hpp"
#include "gateway/dds/written_samples.hpp"

namespace tgw::dds {

/// Fast DDS 2.9 sends a reliable reader's repairs (and a late joiner's history) from its own threads, at once:
/// on a slow link they went ahead of more urgent samples, and after their sample's deadline. The WAN transport
/// hands each message that carries a sample a scheduled write sent before to this desk instead. The desk keeps
/// its bytes and gives the scheduler a core::Repair with that sample's topic and deadline; the scheduler then sends
/// it (send()) or discards it (discard()). Fast DDS takes the message as sent either way: a reader that still
/// misses the sample asks again at the next HEARTBEAT, and once the sample is past its Lifespan (= TTL) the writer
/// answers with a GAP.
/// On a slow link it also paces a large sample: the fragments a scheduled write sends after the first wait here
/// as continuations, so that the schedule puts more urgent samples between them (note_scheduled).
///
/// Thread-safe: scheduled writes and Fast DDS's threads note and hold, the gateway's loop sends and discards.
class RepairDesk {
  public:
    /// Marks one scheduled write on its thread: the samples its messages carry belong to `topic`, due `deadline`.
    /// A reliable writer's are remembered for their repairs; a `latched` writer's (transient local) are repaired
    /// for late joiners past their deadlines too. `payload_bytes`: the sample's, for the scheduler's counts should
    /// its fragments be cut short.
    class WriteScope {
      public:
        WriteScope(core::TopicId topic, base::SteadyTime deadline, bool reliable, bool latched = false,
                   std::size_t payload_bytes = 0);
        ~WriteScope();
        WriteScope(const WriteScope&) = delete;
        WriteScope& operator=(const WriteScope&) = delete;

      private:
        friend class RepairDesk;
        core::TopicId topic_;
        base::SteadyTime deadline_;
        bool reliable_;
        bool latched_;
        std::size_t payload_bytes_;
        /// The sample the write's first message carried: its later fragments are continuations.
        std::optional<RtpsSampleRef> written_;
        std::uint64_t paced_sample_ = 0;  ///< core::Repair::sample of its continuations, once one is held
        WriteScope* outer_;
    };

    /// Watches the writes on its thread while it lives: whether the desk paced the fragments of the sample written
    /// (held them as continuations), so that the writer can keep the sample until its last fragment left (send()
    /// and discard() name it).
    class PacedWatch {
      public:
        PacedWatch();
        ~PacedWatch();
        PacedWatch(const PacedWatch&) = delete;
        PacedWatch& operator=(const PacedWatch&) = delete;

        /// core::Repair::sample of the continuations held, 0 when none was.
        std::uint64_t sample() const { return sample_; }
        std::size_t continuations() const { return continuations_; }
        /// Whether this thread's innermost watch saw continuations held: the sample's payload is still needed.
        static bool holding_here();

      private:
        friend class RepairDesk;
        std::uint64_t sample_ = 0;
        std::size_t continuations_ = 0;
        PacedWatch* outer_;
    };

    /// Sends held messages through `coalescer` (the transport's), in order with everything else it sends. Without
    /// `samples` it holds only the participant's announcements (hold_announcement): compact mode's bundles are
    /// charged as they are repaired.
    RepairDesk(std::shared_ptr<DatagramCoalescer> coalescer, const base::Clock& clock, bool samples = true);

    /// Where repairs go (ForwardingLoop::submit_repair); until it is set, and after stop(), nothing is held.
    void set_submit(std::function<void(const core::Repair&)> submit);
    /// No more holding; what is held is forgotten. Call before the participant's transports go.
    void stop();

    /// Forgets the repairs held for `sender`: its transport is going (the WAN participant made anew). The
    /// schedule's later send() or discard() of them does nothing.
    void forget(const DatagramSender& sender);

    /// A scheduled write's message, when a WriteScope is active on this thread: remembers the samples it carries
    /// (a reliable writer's), and returns true when it holds the message as a continuation, which must not be sent
    /// now: a fragment after the first of the sample the write sent, while pace_fragments is on. `copies` is as in
    /// hold(); `prepaid_bytes` what the write was charged for the message (one copy, without a HEARTBEAT).
    bool note_scheduled(DatagramSender& sender, const DatagramDestination& destination, const std::uint8_t* message,
                        std::size_t size, std::size_t copies, std::size_t prepaid_bytes);
    /// Whether a large sample's fragments after the first wait for the schedule (core::Repair::Kind::continuation);
    /// on a link faster than core::CONTINUATION_PACING_MAX_BPS they leave with the first. Off until set.
    void pace_fragments(bool on) { pace_fragments_.store(on, std::memory_order_relaxed); }
    /// What becomes of a message hold() was given.
    enum class Verdict {
        send,  ///< not the schedule's: send it now
        held,  ///< kept for the schedule (or a repeat of one kept): not to be sent now
        gap,   ///< a repair of samples past their deadlines: send the GAP hold() made instead
    };
    /// A message sent outside any scheduled write, to `copies` of the transport's locators. When it carries a
    /// sample a scheduled write sent whose deadline has not passed, the desk keeps it for the schedule (a repeat
    /// of one it already keeps is forgotten). When every sample it carries is a volatile reliable writer's past its
    /// deadline, `gap` gets a GAP for them: Fast DDS 2.9 was seen answering a reader's NACK_FRAG for a picture 1.6 s
    /// past its deadline and Lifespan, and the reader, told, stops asking.
    Verdict hold(DatagramSender& sender, const DatagramDestination& destination, const std::uint8_t* message,
                 std::size_t size, std::size_t copies, std::vector<std::uint8_t>& gap);

    /// Which of a destination's locators the transport sends to.
    using LocatorFilter = std::function<bool(const eprosima::fastrtps::rtps::Locator_t&)>;
    /// A message sent outside any scheduled write: true when it is the participant's announcement (SPDP). Fast DDS
    /// sends it every 20 s to every base-camp port it knows at once, and three robots' copies met in the channel
    /// just as their hazards did. The desk keeps one copy per locator `supported` takes (a newer announcement to
    /// a locator replaces the one held for it), each a core::Repair of its own, so the schedule sends them one at
    /// a time in their urgency (core::ANNOUNCEMENT_TTL), or at the end of core::ANNOUNCEMENT_WAIT whatever waits.
    bool hold_announcement(DatagramSender& sender, const DatagramDestination& destination, const std::uint8_t* message,
                           std::size_t size, const LocatorFilter& supported);

    /// The topic of a WAN writer's name on the WAN, and its samples' TTL; nullopt for a topic not scheduled (the
    /// status, a camp's command topic).
    struct ScheduledTopic {
        core::TopicId topic = 0;
        base::Duration ttl{};
    };
    using TopicLookup = std::function<std::optional<ScheduledTopic>(std::string_view wan_topic)>;
    /// Where hold_writer_announcement finds a writer's topic; until it is set, none is held.
    void set_topic_lookup(TopicLookup lookup);
    /// A message sent outside any scheduled write: true when it is a WAN writer's announcement (SEDP DATA(w)) of a
    /// scheduled topic, which the desk keeps as a core::Repair::Kind::writer_announcement of that topic, due at
    /// the earlier of its TTL and core::ANNOUNCEMENT_WAIT. At start-up a robot's writers are announced together
    /// (four of the paper's topics: 2 kB, a second of a 20,000 bit/s link), and a hazard's first sample waited
    /// behind a log's announcement past its deadline. A repeat of one held (the camp asking again) is forgotten.
    bool hold_writer_announcement(DatagramSender& sender, const DatagramDestination& destination,
                                  const std::uint8_t* message, std::size_t size, std::size_t copies);

    /// The schedule's decisions on a held repair. send() returns the core::Repair::sample of a continuation (0 for
    /// anything else, or an id no longer held).
    std::uint64_t send(std::uint64_t id);
    void discard(std::uint64_t id);

    struct Counts {
        std::uint64_t held = 0;
        std::uint64_t repeats = 0;  ///< asked again while held: forgotten
        std::uint64_t sent = 0;
        std::uint64_t send_failures = 0;
        std::uint64_t discarded = 0;
        std::uint64_t announcements_held = 0;      ///< copies, one per locator
        std::uint64_t announcements_replaced = 0;  ///< by a newer one to the same locator while held
        std::uint64_t continuations_held = 0;      ///< fragments paced after their sample's first
        std::uint64_t gapped = 0;                  ///< repairs past their samples' deadlines, answered with a GAP
        std::uint64_t writer_announcements_held = 0;
    };
    Counts counts() const;

  private:
    struct Held {
        DatagramSender* sender = nullptr;
        DatagramDestination destination;
        std::vector<std::uint8_t> bytes;
        RtpsSampleRef first;  ///< what it repairs first: a repeat has the same, to the same destination
        core::Repair::Kind kind = core::Repair::Kind::repair;
        std::uint64_t sample = 0;  ///< a continuation's core::Repair::sample
    };
    /// Keeps `message` under a new id and gives the schedule its core::Repair; the lock is held.
    void hold_nts(core::Repair repair, DatagramSender& sender, DatagramDestination destination,
                  const std::uint8_t* message, std::size_t size, const RtpsSampleRef& first);
    /// Forgets what is past its deadline; the lock is held.
    void prune_nts(base::SteadyTime now);
    /// The announcements the schedule left out in a row to `destination` of `sender`: a count for each port.
    struct SkippedAnnouncements {
        const DatagramSender* sender = nullptr;
        DatagramDestination destination;
        int in_a_row = 0;
    };
    /// The count for that port, made at 0 if there is none; the lock is held.
    int& skipped_in_a_row_nts(const DatagramSender& sender, const DatagramDestination& destination);

    const std::shared_ptr<DatagramCoalescer> coalescer_;
    const base::Clock& clock_;
    const bool samples_;
    std::atomic<bool> pace_fragments_{false};
    mutable std::mutex mutex_;
    std::function<void(const core::Repair&)> submit_;
    TopicLookup topic_lookup_;
    bool stopped_ = false;
    /// With the volatile writers among them: a repair of theirs not there any more is of a sample past its
    /// deadline.
    WrittenSamples written_;
    base::SteadyTime next_prune_{};
    std::unordered_map<std::uint64_t, Held> held_;
    std::vector<SkippedAnnouncements> skipped_;  // a few ports
    std::uint64_t next_id_ = 1;
    std::uint64_t next_paced_sample_ = 1;
    Counts counts_;
};

}  // namespace tgw::dds
