#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <fastrtps/types/TypesBase.h>

#include "base/clock.hpp"
#include "core/sample.hpp"
#include "gateway/dds/latched_history.hpp"
#include "passthrough/writer_match_counter.hpp"

namespace eprosima::fastdds::dds {
class DataWriter;
}

namespace tgw::dds {

/// Outcome of one write, counted by the caller; nothing on this path throws.
enum class WriteResult { ok, unknown_topic, failed };

/// What the caller of a write does with the sample's payload once it is written: a latched writer, which keeps each
/// instance's last change, takes a spent one instead of copying it.
enum class AfterWrite { payload_needed, payload_spent };

/// One lane's DataWriter on the WAN domain (made by WanRouter::create_writer): writes, disposes and unregisters
/// with the sample's source timestamp and instance, and counts the base-camp readers it matches. It deletes the
/// writer when the last holder lets go of it, so a write in progress finishes first; every holder must let go
/// before the WAN router goes. When the router makes its participant anew (an address change), it detaches the
/// writer and gives it its successor on the new participant: holders keep the same WanWriter, and a transient-local
/// writer's successor is given the last change of each instance again (LatchedHistory).
class WanWriter {
  public:
    /// Deletes a writer when its WanWriter goes (WanRouter's, which deletes the topic with its last writer).
    using Deleter = std::function<void(eprosima::fastdds::dds::DataWriter*)>;

    /// Takes `writer`, which must have been created with `matches` as its listener; `deleter` deletes it.
    WanWriter(eprosima::fastdds::dds::DataWriter* writer, std::unique_ptr<passthrough::WriterMatchCounter> matches,
              std::string topic, bool keyed, Deleter deleter);
    ~WanWriter();

    WanWriter(const WanWriter&) = delete;
    WanWriter& operator=(const WanWriter&) = delete;

    /// The sample keeps its payload, so that a refused write can still be logged; after a write that succeeded,
    /// a latched writer takes a `payload_spent` one (unless the repair desk holds the sample's continuations:
    /// RepairDesk::PacedWatch) and leaves the sample without it. Never throws.
    WriteResult write(core::Sample& sample, AfterWrite after = AfterWrite::payload_needed);

    /// No writer until replace(): the participant is going. Waits for a write in progress; later writes fail.
    void detach();
    /// The successor of the detached writer, made with match_listener() as its listener; a transient-local one is
    /// written what the camp's late joiners must get.
    void replace(eprosima::fastdds::dds::DataWriter* writer);
    /// The listener a successor must be made with.
    passthrough::WriterMatchCounter* match_listener() const { return matches_.get(); }

    /// Base-camp readers matched now.
    std::int32_t matched_readers() const { return matches_->matched.load(); }
    /// The writer's Lifespan QoS; nullopt when it is infinite.
    std::optional<base::Duration> lifespan() const { return lifespan_; }

  private:
    eprosima::fastrtps::types::ReturnCode_t write_nts(core::Sample& sample);

    mutable std::mutex mutex_;                    // a write against detach() and replace()
    eprosima::fastdds::dds::DataWriter* writer_;  // under mutex_; null while detached
    std::unique_ptr<passthrough::WriterMatchCounter> matches_;
    Deleter deleter_;
    const std::string topic_;
    const bool keyed_;
    const bool reliable_;
    const bool latched_;  ///< transient local: a late joiner gets its history, past deadlines too
    const std::optional<base::Duration> lifespan_;
    LatchedHistory latched_history_;  // under mutex_; a transient-local writer's only
    std::atomic<bool> failure_reported_{false};
};

}  // namespace tgw::dds
