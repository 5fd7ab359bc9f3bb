#include "core/bundle_builder.hpp"

#include "compact/bundle_codec.hpp"

namespace tgw::core {

BundleBuilder::Entry BundleBuilder::Entry::of(TopicId topic, std::uint16_t lane, base::WallTime source_time,
                                              const std::vector<std::uint8_t>& payload, bool keyed) {
    return Entry{
        topic, lane,   source_time, payload.size(), compact::BundleCodec::plain_cdr(payload.data(), payload.size()),
        keyed, nullptr};
}

std::size_t BundleBuilder::entry_bytes(const Entry& entry) const {
    // The first entry sets the bundle's base time: its own delta is 0.
    const base::WallTime base = entries_ == 0 ? entry.source_time : base_time_;
    // In unsigned arithmetic, as the codec does: far-apart clocks wrap instead of overflowing.
    const auto ns = [](base::WallTime t) {
        return static_cast<std::uint64_t>(
            std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count());
    };
    const auto delta_ns = static_cast<std::int64_t>(ns(entry.source_time) - ns(base));
    compact::ChunkInfo chunk;
    if (entry.chunk != nullptr) {
        chunk = compact::ChunkInfo{entry.chunk->id, entry.chunk->total_bytes, entry.chunk->offset};
    }
    return compact::BundleCodec::entry_bytes(entry.topic, entry.lane, delta_ns, entry.payload_bytes, entry.plain_cdr,
                                             entry.keyed, entry.chunk != nullptr ? &chunk : nullptr);
}

std::size_t BundleBuilder::encoded_bytes() const {
    return compact::BundleCodec::MAX_FRAME_BYTES + entry_bytes_;
}

std::size_t BundleBuilder::encoded_bytes_with(const Entry& entry) const {
    return encoded_bytes() + entry_bytes(entry);
}

std::uint64_t BundleBuilder::alone_wire_bits(const Entry& entry) const {
    return wire_bits(compact::BundleCodec::MAX_FRAME_BYTES + BundleBuilder(wire_).entry_bytes(entry));
}

void BundleBuilder::add(const Entry& entry) {
    entry_bytes_ += entry_bytes(entry);
    if (entries_ == 0) {
        base_time_ = entry.source_time;
    }
    ++entries_;
}

}  // namespace tgw::core
