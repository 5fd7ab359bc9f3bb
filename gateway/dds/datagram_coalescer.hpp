// Packs the WAN samples that follow each other closely into shared datagrams, without a thread hand-off for a
// sample that comes alone.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <fastdds/rtps/common/Locator.h>

#include "base/clock.hpp"
#include "wire/rtps_datagram.hpp"

namespace tgw::dds {

/// Where a datagram goes: the low-level transport's channel and its destination locators.
struct DatagramDestination {
    const void* channel = nullptr;
    std::vector<eprosima::fastrtps::rtps::Locator_t> locators;

    bool operator==(const DatagramDestination& other) const {
        return channel == other.channel && locators == other.locators;
    }
};

/// Sends one datagram now; true when the transport took it.
class DatagramSender {
  public:
    virtual ~DatagramSender() = default;
    virtual bool send_datagram(const DatagramDestination& destination, const std::uint8_t* bytes, std::size_t size) = 0;
};

/// What DatagramCoalescer::hold does with a reliable writer's control alone.
struct HeldControl {
    base::Duration wait{};  ///< 0: nothing is held
    /// Told what a held message came to on the wire as it leaves, frames included, every copy.
    std::function<void(std::uint64_t frame_bytes)> on_sent;
};

/// Decides, per RTPS message the WAN participant sends, whether it goes now or waits to share a datagram.
///
/// Only messages sent while a DeferScope lives on the sending thread may wait: the gateway's WAN writes. A
/// message to a destination that has seen no datagram for `window` goes at once, as without coalescing, so a
/// sample that comes alone pays no hand-off. One that follows closer waits, at most `window`, for more to the
/// same destination; the datagram goes when it is full or when the window ends (the flush thread). A message that
/// fills a datagram alone (less than a sixteenth of it left) goes at once, whenever it comes. A write's
/// messages (a large sample's fragments) all go at once or all may wait, as its first did. Any other
/// send to that destination (heartbeats, discovery) sends what waits first, so nothing overtakes.
///
/// The scheduler's wire model still counts one RTPS header per sample: coalescing only sends less than it.
class DatagramCoalescer {
  public:
    /// Wraps one write: while it lives on a thread, that thread's messages may wait. Nests.
    class DeferScope {
      public:
        DeferScope();
        ~DeferScope();
        DeferScope(const DeferScope&) = delete;
        DeferScope& operator=(const DeferScope&) = delete;
        /// The innermost scope on this thread, unique in the process; 0 outside any.
        static std::uint64_t current();

      private:
        std::uint64_t outer_;
    };

    /// Long enough to pack the samples of a burst on a fast link, short beside any TTL.
    static constexpr std::chrono::microseconds DEFAULT_WINDOW{100};

    /// Short beside the TTLs of the samples a HEARTBEAT announces, long beside the gap between two samples to a
    /// base camp while any flow (5 Hz and more for a robot's state).
    static constexpr base::Duration DEFAULT_CONTROL_WAIT = std::chrono::milliseconds(250);

    /// `window` 0 sends everything at once. `max_datagram_bytes`: the low-level transport's message size.
    DatagramCoalescer(std::chrono::microseconds window, std::size_t max_datagram_bytes, const base::Clock& clock,
                      HeldControl held_control = {});
    ~DatagramCoalescer();

    DatagramCoalescer(const DatagramCoalescer&) = delete;
    DatagramCoalescer& operator=(const DatagramCoalescer&) = delete;

    /// Starts the thread that sends datagrams whose window ended.
    void start();
    /// Sends what waits and stops the thread; from then on every message goes at once. Call before the
    /// low-level channels go away.
    void stop();

    /// Sends what waits for `sender` and forgets it: its transport is going (the WAN participant made anew).
    void forget(const DatagramSender& sender);

    /// Sends `message` now or keeps a copy to send with the next ones. False only when a send now failed.
    bool send(DatagramSender& sender, const DatagramDestination& destination, const std::uint8_t* message,
              std::size_t size);

    /// Keeps `message`, a reliable writer's HEARTBEATs or GAPs alone (RtpsDatagram::user_control_only), up to the
    /// HeldControl's wait for the next message to the same destination, and sends it in that one's datagram: its
    /// bytes but its 20-byte header, where alone it is a datagram of its own (110 bytes for a HEARTBEAT, frames
    /// included). Fast DDS sends a writer's periodic HEARTBEATs on the writer's own timer, apart from its
    /// samples; the next sample to that base camp follows them soon. Goes at once when the wait is 0.
    /// `copies`: the destination's locators the transport sends to.
    bool hold(DatagramSender& sender, const DatagramDestination& destination, const std::uint8_t* message,
              std::size_t size, std::size_t copies);
    bool holds_control() const { return held_control_.wait > base::Duration::zero(); }

    /// Sends the datagrams whose window has ended by the clock's now: the flush thread's step.
    void flush_due();

    /// What the messages sent in a DeferScope came to.
    struct Counts {
        std::uint64_t messages = 0;
        std::uint64_t datagrams = 0;  ///< that carried them
        /// Datagrams that waited and then failed to send: their writers had been told the write succeeded.
        std::uint64_t failed_datagrams = 0;
        std::uint64_t controls_held = 0;  ///< hold()'s messages
        std::uint64_t controls_rode = 0;  ///< of those, sent in the datagram of another message
    };
    Counts counts() const;

  private:
    struct Batch {
        DatagramSender* sender = nullptr;
        DatagramDestination destination;
        wire::RtpsDatagram datagram;
        base::SteadyTime deadline{};
        base::SteadyTime last_sent{};
        std::uint64_t sent_at_once_scope = 0;  ///< the last write whose messages went at once
        /// `datagram` holds hold()'s messages alone, not yet charged; `control_messages` of them.
        bool control_only = false;
        std::size_t control_messages = 0;
        std::size_t copies = 1;
        explicit Batch(std::size_t max_bytes) : datagram(max_bytes) {}
    };

    Batch& batch_for_nts(DatagramSender& sender, const DatagramDestination& destination);
    /// A message of `size` leaves its datagram less room than 1 / FULL_DATAGRAM_ROOM_FRACTION of it: what could
    /// ride in the rest would save less than holding the message costs.
    static constexpr std::size_t FULL_DATAGRAM_ROOM_FRACTION = 16;
    bool fills_datagram(std::size_t size) const;
    Batch* find_nts(const DatagramSender& sender, const DatagramDestination& destination);
    bool send_now_nts(Batch& batch, const std::uint8_t* bytes, std::size_t size, base::SteadyTime now);
    void flush_nts(Batch& batch, base::SteadyTime now);
    /// Appends `message` to the held control messages of `batch` and sends them together: whether the transport
    /// took the datagram; nullopt, nothing sent, when it does not fit.
    std::optional<bool> send_with_held_control_nts(Batch& batch, const std::uint8_t* message, std::size_t size);
    bool send_nts(std::unique_lock<std::mutex>& lock, DatagramSender& sender, const DatagramDestination& destination,
                  const std::uint8_t* message, std::size_t size);
    /// Tells HeldControl::on_sent what the held messages that left came to, with the lock released meanwhile.
    void report_charges(std::unique_lock<std::mutex>& lock);
    void flush_due_nts(base::SteadyTime now);
    void run();

    const std::chrono::microseconds window_;
    const std::size_t max_datagram_bytes_;
    const base::Clock& clock_;
    const HeldControl held_control_;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::vector<std::unique_ptr<Batch>> batches_;  // few: one per destination set
    bool stopping_ = false;
    bool stopped_ = false;
    bool kicked_ = false;
    std::thread thread_;
    Counts counts_;
    std::uint64_t pending_charge_ = 0;  ///< frame bytes of held messages that left, not yet reported
};

}  // namespace tgw::dds
