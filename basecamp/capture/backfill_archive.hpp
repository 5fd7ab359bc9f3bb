// The base camp's end of backfill (docs/design/backfill.md): what a gateway's on-robot log kept reaches the camp's
// recording, never its live domain (it is past its TTL), and each row stored is acknowledged once committed.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <vector>

#include "BackfillPubSubTypes.h"
#include "basecamp/recording/sample_store.hpp"

namespace tgw::basecamp {

/// Stores backfilled samples in a recording and gathers the acknowledgements of those stored. Thread-safe.
class BackfillArchive {
  public:
    /// Rows go into `store`, whose acknowledgement callback (SampleStore::on_backfill_stored) this takes; `store`
    /// must outlive it, and no sample may have been added to it yet.
    explicit BackfillArchive(SampleStore& store);
    /// Takes its callback back from the store, waiting for a call in progress: the store's writer thread may still
    /// commit rows after this is gone (a camp tool destroys it before the store).
    ~BackfillArchive();
    BackfillArchive(const BackfillArchive&) = delete;
    BackfillArchive& operator=(const BackfillArchive&) = delete;

    /// A sample taken off the backfill topic, arrived at `receive_ns` (wall clock): into the store, as a sample of
    /// its own topic and type, with its source time and its origin (log, row, why it stayed on the robot).
    void take(const idl::BackfillSample& sample, std::int64_t receive_ns);
    /// The acknowledgements due, one per log with rows committed since the last call, stamped `sent_ns`.
    std::vector<idl::BackfillAck> take_acks(std::uint64_t sent_ns);

    /// Backfilled samples taken so far, duplicates included.
    std::uint64_t received() const { return received_.load(); }
    /// Rows acknowledged so far (a duplicate is acknowledged again, and counted again).
    std::uint64_t acknowledged() const { return acknowledged_.load(); }

  private:
    /// Called by the store once a row is committed.
    void stored(const std::string& log_id, std::int64_t row_id);

    SampleStore& store_;
    std::mutex mutex_;
    std::map<std::array<std::uint8_t, 16>, std::vector<std::int64_t>> committed_;  // under mutex_
    std::atomic<std::uint64_t> received_{0};
    std::atomic<std::uint64_t> acknowledged_{0};
};

}  // namespace tgw::basecamp
