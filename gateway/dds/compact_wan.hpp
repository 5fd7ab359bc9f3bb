#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "CompactWan.h"
#include "base/time.hpp"
#include "compact/bundle_codec.hpp"
#include "core/sample.hpp"
#include "core/sample_sink.hpp"
#include "core/wire_model.hpp"
#include "passthrough/offered_qos.hpp"

namespace tgw::dds {

class WanRouter;
class WanWriter;

/// One lane of a bridged topic, as the catalog tells the base camp about it.
struct CatalogLane {
    core::TopicId topic_id = 0;
    std::string topic;
    std::string type_name;
    bool keyed = false;
    base::Duration ttl{};
    std::uint16_t lane = 0;
    passthrough::OfferedQos offer;
    std::optional<base::Duration> lifespan;  ///< what the relay republishes with; nullopt: infinite
    /// Its samples travel as one zstd frame each (the gateway compressed them), which the relay decompresses.
    bool zstd_payload = false;
};

/// The gateway's side of the compact WAN mode (--wan-mode compact): instead of a WAN writer per lane, one
/// best-effort writer of bundles (what the scheduler released together, compact::BundleCodec), and a reliable,
/// transient-local catalog that maps each topic id to its topic, type, key kind, TTL and the QoS of each lane.
class CompactWan {
  public:
    /// Creates both writers on `wan`'s participant. Throws base::ConfigError when Fast DDS refuses one.
    CompactWan(WanRouter& wan, const core::WireModel& wire, compact::BundleCompression compression);
    ~CompactWan();

    CompactWan(const CompactWan&) = delete;
    CompactWan& operator=(const CompactWan&) = delete;

    /// Adds the lane to its topic's catalog entry and writes the entry (again). False (after logging it) when the
    /// write failed. Any thread.
    bool announce(const CatalogLane& lane);

    /// Writes every catalog entry again: the catalog's writer was made anew, its history empty
    /// (WanRouter::rebind). False (after logging it) when a write failed.
    bool announce_again();

    /// Encodes `samples` as the next bundle into `out` (the bundle's DDS sample) and returns the bytes it will put
    /// on the link (the wire model of its encoded size); the samples keep their payloads. No I/O: the forwarding
    /// loop calls it under its lock, one thread at a time, and sends the bundles after it, in the same order. A
    /// bundle that is encoded but not sent leaves a gap in the sequence, which the relay counts as lost.
    std::size_t encode(std::vector<core::Sample>& samples, core::EncodedBundle& out);
    /// Writes a bundle `encode` made, of `entries` samples. False when the write failed. One thread at a time.
    bool send(core::EncodedBundle&& bundle, std::size_t entries);

    /// What the bundles written so far were like.
    struct Stats {
        std::uint64_t bundles = 0;
        std::uint64_t entries = 0;
        std::uint64_t encoded_bytes = 0;  ///< after compression
        std::uint64_t wire_bytes = 0;     ///< the wire model's, as charged
        base::SteadyTime first{};         ///< when the first and the last were written
        base::SteadyTime last{};
    };

    /// Base-camp readers of the bundles matched now.
    std::int32_t matched_readers() const;
    Stats stats() const;

  private:
    /// Under catalog_mutex_.
    bool write_entry_nts(wan::CatalogEntry& entry);

    core::WireModel wire_;
    compact::BundleCompression compression_;
    std::shared_ptr<WanWriter> bundle_writer_;
    std::shared_ptr<WanWriter> catalog_writer_;
    std::mutex catalog_mutex_;
    std::map<core::TopicId, wan::CatalogEntry> catalog_;  // under catalog_mutex_
    std::uint32_t next_sequence_ = 0;
    compact::Bundle bundle_;             ///< encode()'s, reused
    std::vector<std::uint8_t> encoded_;  ///< encode()'s, reused
    core::Sample carrier_;               ///< send()'s: the bundle's DDS sample
    mutable std::mutex stats_mutex_;
    Stats stats_;  // under stats_mutex_
};

}  // namespace tgw::dds
