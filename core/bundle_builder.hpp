#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/sample.hpp"
#include "core/wire_model.hpp"

namespace tgw::core {

/// Compact WAN mode: how large a bundle may grow (its encoding, compact::BundleCodec).
struct BundleLimits {
    /// The bundle travels as one DDS sample: its encapsulation and the sequence's length come first.
    static constexpr std::size_t DDS_ENVELOPE_BYTES = 8;
    /// Bytes kept clear of Fast DDS's own limit: at the limit itself, bundles were sent as DATA_FRAG (measured on
    /// the testbed, 2026-11-25), and a fragmented bundle arrived corrupt now and then (its CRC caught it).
    static constexpr std::size_t FRAGMENTATION_MARGIN_BYTES = 16;
    /// The largest encoding that leaves in one DATA submessage, with the margin (1284 at the default 1472), and
    /// with DDS Security room for what protection adds (WireModel::payload_overhead_bytes,
    /// WireModel::protected_fill_margin_bytes).
    static std::size_t one_datagram(const WireModel& wire) {
        return wire.max_unfragmented_bytes - wire.payload_overhead_bytes - wire.protected_fill_margin_bytes -
               DDS_ENVELOPE_BYTES - FRAGMENTATION_MARGIN_BYTES;
    }

    std::size_t max_encoded_bytes = one_datagram(WireModel{});
};

/// The bundle the scheduler is filling: the sizes of what it holds so far, so that the budget charges what the
/// bundle will really put on the wire, and the scheduler can ask what one more sample would cost.
class BundleBuilder {
  public:
    /// What the builder needs to know of a sample, or of a chunk of one.
    struct Entry {
        TopicId topic;
        std::uint16_t lane;
        base::WallTime source_time;
        std::size_t payload_bytes;
        bool plain_cdr;  ///< the payload begins with the plain CDR header (compact::BundleCodec::plain_cdr)
        bool keyed;
        const Sample::Chunk* chunk = nullptr;

        /// The entry of a whole sample (`payload` is what the size and the header are read from).
        static Entry of(TopicId topic, std::uint16_t lane, base::WallTime source_time,
                        const std::vector<std::uint8_t>& payload, bool keyed);
    };

    explicit BundleBuilder(const WireModel& wire) : wire_(wire) {}

    bool empty() const { return entries_ == 0; }
    std::size_t entries() const { return entries_; }
    /// The encoding's bytes so far, the header and checksum counted at their largest.
    std::size_t encoded_bytes() const;
    /// The encoding's bytes if `entry` joined.
    std::size_t encoded_bytes_with(const Entry& entry) const;
    /// What a bundle of `encoded_bytes` puts on the link: one DDS sample, fragmented if it must be.
    std::uint64_t wire_bits(std::size_t encoded_bytes) const {
        return wire_.wire_bits(encoded_bytes + BundleLimits::DDS_ENVELOPE_BYTES);
    }
    /// What a bundle holding `entry` alone puts on the link.
    std::uint64_t alone_wire_bits(const Entry& entry) const;

    void add(const Entry& entry);
    void clear() { *this = BundleBuilder(wire_); }

  private:
    std::size_t entry_bytes(const Entry& entry) const;

    WireModel wire_;
    std::size_t entries_ = 0;
    std::size_t entry_bytes_ = 0;
    base::WallTime base_time_{};
};

/// Splits a bundle's bytes among its entries, each its payload's share of the whole (equal shares when every
/// payload is empty), rounded so that the shares add up to the bundle. Call next() once per entry, in order.
class BundleShares {
  public:
    BundleShares(std::uint64_t bundle_bytes, std::uint64_t payload_bytes, std::size_t entries)
        : bundle_bytes_(bundle_bytes), payload_bytes_(payload_bytes), entries_(entries) {}

    std::uint64_t next(std::size_t entry_payload_bytes) {
        const std::uint64_t before = share_until(payload_before_, index_);
        payload_before_ += entry_payload_bytes;
        ++index_;
        return share_until(payload_before_, index_) - before;
    }

  private:
    std::uint64_t share_until(std::uint64_t payload, std::size_t entries) const {
        if (entries_ == 0) {
            return 0;
        }
        return payload_bytes_ == 0 ? bundle_bytes_ * entries / entries_ : bundle_bytes_ * payload / payload_bytes_;
    }

    std::uint64_t bundle_bytes_;
    std::uint64_t payload_bytes_;
    std::size_t entries_;
    std::uint64_t payload_before_ = 0;
    std::size_t index_ = 0;
};

}  // namespace tgw::core
