#include "gateway/dds/compact_wan.hpp"

#include <iostream>
#include <utility>

#include <fastdds/rtps/common/SerializedPayload.h>

#include "CompactWanPubSubTypes.h"
#include "base/config_error.hpp"
#include "compact/bundle_codec.hpp"
#include "core/bundle_builder.hpp"
#include "gateway/dds/keyed_sample.hpp"
#include "gateway/dds/unstamped_write.hpp"
#include "gateway/dds/wan_router.hpp"
#include "gateway/dds/wan_writer.hpp"
#include "wire/compact_topics.hpp"

namespace tgw::dds {

namespace {

std::int64_t ns_or_infinite(const std::optional<base::Duration>& d) {
    return d ? std::chrono::duration_cast<std::chrono::nanoseconds>(*d).count() : -1;
}

wan::LaneOffer lane_offer(const CatalogLane& lane) {
    wan::LaneOffer out;
    const passthrough::OfferedQos& o = lane.offer;
    out.reliable(o.reliable);
    out.transient_local(o.transient_local);
    out.partitions(o.partitions);
    out.deadline_ns(ns_or_infinite(o.deadline));
    out.liveliness(static_cast<std::uint8_t>(o.liveliness));
    out.liveliness_lease_ns(ns_or_infinite(o.liveliness_lease));
    out.exclusive_ownership(o.exclusive_ownership);
    out.ownership_strength(o.ownership_strength);
    out.xcdr2(o.xcdr2);
    out.lifespan_ns(ns_or_infinite(lane.lifespan));
    return out;
}

compact::EntryKind entry_kind(core::SampleKind kind) {
    switch (kind) {
        case core::SampleKind::dispose:
            return compact::EntryKind::dispose;
        case core::SampleKind::unregister:
            return compact::EntryKind::unregister;
        case core::SampleKind::data:
            break;
    }
    return compact::EntryKind::data;
}

}  // namespace

CompactWan::CompactWan(WanRouter& wan, const core::WireModel& wire, compact::BundleCompression compression)
    : wire_(wire), compression_(compression) {
    passthrough::OfferedQos best_effort;
    bundle_writer_ = wan.create_writer(wire::COMPACT_BUNDLE_TOPIC, wire::COMPACT_BUNDLE_TOPIC,
                                       wan::BundlePubSubType().getName(), false, std::nullopt, best_effort, nullptr);
    passthrough::OfferedQos latched;
    latched.reliable = true;
    latched.transient_local = true;
    catalog_writer_ = wan.create_writer(wire::COMPACT_CATALOG_TOPIC, wire::COMPACT_CATALOG_TOPIC,
                                        wan::CatalogEntryPubSubType().getName(), true, std::nullopt, latched, nullptr);
    if (bundle_writer_ == nullptr || catalog_writer_ == nullptr) {
        throw base::ConfigError("--wan-mode compact: cannot create the WAN writers of " +
                                std::string(wire::COMPACT_BUNDLE_TOPIC) + " and " + wire::COMPACT_CATALOG_TOPIC);
    }
}

CompactWan::~CompactWan() = default;

bool CompactWan::announce(const CatalogLane& lane) {
    std::lock_guard<std::mutex> lock(catalog_mutex_);
    wan::CatalogEntry& entry = catalog_[lane.topic_id];
    entry.topic_id(lane.topic_id);
    entry.topic(lane.topic);
    entry.type_name(lane.type_name);
    entry.keyed(lane.keyed);
    entry.ttl_ns(std::chrono::duration_cast<std::chrono::nanoseconds>(lane.ttl).count());
    entry.zstd_payload(lane.zstd_payload);
    if (entry.lanes().size() <= lane.lane) {
        entry.lanes().resize(lane.lane + 1u);
    }
    entry.lanes()[lane.lane] = lane_offer(lane);
    return write_entry_nts(entry);
}

bool CompactWan::announce_again() {
    std::lock_guard<std::mutex> lock(catalog_mutex_);
    bool all = true;
    for (auto& [id, entry] : catalog_) {
        all = write_entry_nts(entry) && all;
    }
    return all;
}

bool CompactWan::write_entry_nts(wan::CatalogEntry& entry) {
    wan::CatalogEntryPubSubType type;
    core::Sample sample;
    if (!keyed_sample(type, entry, sample)) {
        std::cerr << "telemetry-gateway: cannot serialize the catalog entry of " << entry.topic() << "\n";
        return false;
    }
    sample.source_time = base::WallClock::now();
    // Reliable and latched: a base camp that misses it, or joins later, gets it repaired or on joining.
    return catalog_writer_->write(sample) == WriteResult::ok;
}

std::size_t CompactWan::encode(std::vector<core::Sample>& samples, core::EncodedBundle& out) {
    bundle_.sequence = next_sequence_++;
    // Written a moment after it is encoded (ForwardingLoop writes after deciding): the relay's one-way delay.
    bundle_.write_ns = base::to_ns(base::WallClock::now());
    bundle_.entries.resize(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        core::Sample& sample = samples[i];
        compact::BundleEntry& entry = bundle_.entries[i];
        entry.topic_id = sample.topic;
        entry.lane = sample.route;
        entry.kind = entry_kind(sample.kind);
        entry.source_ns =
            std::chrono::duration_cast<std::chrono::nanoseconds>(sample.source_time.time_since_epoch()).count();
        entry.keyed = sample.key.valid;
        entry.key = sample.key.bytes;
        entry.chunked = sample.chunk.has_value();
        if (sample.chunk) {
            entry.chunk = compact::ChunkInfo{sample.chunk->id, sample.chunk->total_bytes, sample.chunk->offset};
        }
        entry.payload = std::move(sample.payload);  // handed back below
    }
    compact::BundleCodec::encode(bundle_, encoded_, compression_);
    for (std::size_t i = 0; i < samples.size(); ++i) {
        samples[i].payload = std::move(bundle_.entries[i].payload);
    }

    // The DDS sample: plain CDR of wan::Bundle, the sequence's length and the bytes.
    const auto length = static_cast<std::uint32_t>(encoded_.size());
    const std::uint8_t envelope[core::BundleLimits::DDS_ENVELOPE_BYTES] = {0x00,
                                                                           0x01,
                                                                           0x00,
                                                                           0x00,
                                                                           static_cast<std::uint8_t>(length),
                                                                           static_cast<std::uint8_t>(length >> 8),
                                                                           static_cast<std::uint8_t>(length >> 16),
                                                                           static_cast<std::uint8_t>(length >> 24)};
    out.bytes.assign(std::begin(envelope), std::end(envelope));
    out.bytes.insert(out.bytes.end(), encoded_.begin(), encoded_.end());
    out.wire_bytes = wire_.wire_bytes(out.bytes.size());
    return out.wire_bytes;
}

bool CompactWan::send(core::EncodedBundle&& bundle, std::size_t entries) {
    std::swap(carrier_.payload, bundle.bytes);  // the carrier's buffer goes back to be reused or freed
    carrier_.source_time = base::WallClock::now();
    const WriteResult written = [&] {
        // The bundle holds its write time: the transport leaves the INFO_TS out (WanConfig::strip_timestamp).
        const UnstampedWrite unstamped;
        return bundle_writer_->write(carrier_);
    }();
    if (written != WriteResult::ok) {
        return false;
    }
    const std::size_t wire_bytes = bundle.wire_bytes;
    const std::size_t encoded_bytes = carrier_.payload.size() - core::BundleLimits::DDS_ENVELOPE_BYTES;
    const base::SteadyTime now = base::SteadyClock::now();
    std::lock_guard<std::mutex> lock(stats_mutex_);
    if (stats_.bundles == 0) {
        stats_.first = now;
    }
    ++stats_.bundles;
    stats_.entries += entries;
    stats_.encoded_bytes += encoded_bytes;
    stats_.wire_bytes += wire_bytes;
    stats_.last = now;
    return true;
}

CompactWan::Stats CompactWan::stats() const {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    return stats_;
}

std::int32_t CompactWan::matched_readers() const {
    return bundle_writer_->matched_readers();
}

}  // namespace tgw::dds
