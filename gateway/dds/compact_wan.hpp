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
#include "gateway/compact/bundle_codec.hpp"
#include "gateway/core/sample.hpp"
#include "gateway/core/wire_model.hpp"
#include "gateway/dds/offered_qos.hpp"

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
    OfferedQos offer;
    std::optional<base::Duration> lifespan;  ///< what the relay republishes with; nullopt: infinite
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

    /// Encodes `samples` as the next bundle and writes it. Returns the bytes it put on the link (the wire model of
    /// its encoded size), or 0 when the write failed; the samples keep their payloads either way. Called by one
    /// thread at a time (the forwarding loop's).
    std::size_t write(std::vector<core::Sample>& samples);

    /// Base-camp readers of the bundles matched now.
    std::int32_t matched_readers() const;
    std::uint64_t bundles_written() const { return bundles_written_.load(); }
    /// The bundles' encoded bytes (after compression) and the entries' payload bytes, so far.
    std::uint64_t bundle_bytes() const { return bundle_bytes_.load(); }

  private:
    core::WireModel wire_;
    compact::BundleCompression compression_;
    std::shared_ptr<WanWriter> bundle_writer_;
    std::shared_ptr<WanWriter> catalog_writer_;
    std::mutex catalog_mutex_;
    std::map<core::TopicId, wan::CatalogEntry> catalog_;  // under catalog_mutex_
    std::uint32_t next_sequence_ = 0;
    compact::Bundle bundle_;             ///< reused between writes
    std::vector<std::uint8_t> encoded_;  ///< reused between writes
    std::atomic<std::uint64_t> bundles_written_{0};
    std::atomic<std::uint64_t> bundle_bytes_{0};
};

}  // namespace tgw::dds
