// Packs the WAN samples that follow each other closely into shared datagrams, without a thread hand-off for a
// sample that comes alone.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <fastdds/rtps/common/Locator.h>

#include "base/clock.hpp"
#include "gateway/dds/rtps_datagram.hpp"

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

/// Decides, per RTPS message the WAN participant sends, whether it goes now or waits to share a datagram.
///
/// Only messages sent while a DeferScope lives on the sending thread may wait: the gateway's WAN writes. A
/// message to a destination that has seen no datagram for `window` goes at once, as without coalescing, so a
/// sample that comes alone pays no hand-off. One that follows closer waits, at most `window`, for more to the
/// same destination; the datagram goes when it is full or when the window ends (the flush thread). A write's
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

    /// `window` 0 sends everything at once. `max_datagram_bytes`: the low-level transport's message size.
    DatagramCoalescer(std::chrono::microseconds window, std::size_t max_datagram_bytes, const base::Clock& clock);
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

    /// Sends the datagrams whose window has ended by the clock's now: the flush thread's step.
    void flush_due();

    /// What the messages sent in a DeferScope came to.
    struct Counts {
        std::uint64_t messages = 0;
        std::uint64_t datagrams = 0;  ///< that carried them
        /// Datagrams that waited and then failed to send: their writers had been told the write succeeded.
        std::uint64_t failed_datagrams = 0;
    };
    Counts counts() const;

  private:
    struct Batch {
        DatagramSender* sender = nullptr;
        DatagramDestination destination;
        RtpsDatagram datagram;
        base::SteadyTime deadline{};
        base::SteadyTime last_sent{};
        std::uint64_t sent_at_once_scope = 0;  ///< the last write whose messages went at once
        explicit Batch(std::size_t max_bytes) : datagram(max_bytes) {}
    };

    Batch& batch_for_nts(DatagramSender& sender, const DatagramDestination& destination);
    Batch* find_nts(const DatagramSender& sender, const DatagramDestination& destination);
    bool send_now_nts(Batch& batch, const std::uint8_t* bytes, std::size_t size, base::SteadyTime now);
    void flush_nts(Batch& batch, base::SteadyTime now);
    void flush_due_nts(base::SteadyTime now);
    void run();

    const std::chrono::microseconds window_;
    const std::size_t max_datagram_bytes_;
    const base::Clock& clock_;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::vector<std::unique_ptr<Batch>> batches_;  // few: one per destination set
    bool stopping_ = false;
    bool stopped_ = false;
    bool kicked_ = false;
    std::thread thread_;
    Counts counts_;
};

}  // namespace tgw::dds
