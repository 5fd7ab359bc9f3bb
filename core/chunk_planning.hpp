// Compact mode: the sizes and times a sample too large for one bundle plans on as it leaves in chunks.
#pragma once

#include <cstddef>
#include <cstdint>

#include "base/time.hpp"
#include "core/bundle_builder.hpp"
#include "core/link_budget.hpp"
#include "core/sample.hpp"
#include "core/wire_model.hpp"

namespace tgw::core {

/// A sample leaves in chunks, one a bundle, when it is larger than a bundle or would hold the link longer than the
/// non-preemptive rule allows; urgent samples travel between its chunks. These are the plans it is started on (a
/// sample abandoned halfway wastes every chunk it sent). docs/design.md §8.
class ChunkPlanning {
  public:
    ChunkPlanning(const WireModel& wire, const BundleLimits& limits, base::Duration link_latency)
        : wire_(wire), limits_(limits), link_latency_(link_latency) {}

    /// The least a sample of `payload_bytes` puts on the link in chunks: the whole link its own, a chunk a bundle.
    std::uint64_t chunk_bits(std::size_t payload_bytes) const;
    /// When the last chunk of a sample of `payload_bytes` started at `start` arrives, given `rate_left_bps` of the
    /// link that the more urgent topics left it lately (planned on with a margin); SteadyTime::max() for none.
    base::SteadyTime chunks_arrive_by(std::size_t payload_bytes, base::SteadyTime start, double rate_left_bps,
                                      const LinkBudget& budget) const;
    /// A sample that does not fit the room a bundle has left may fill it with its first chunk when its rest fits
    /// one more bundle...
    bool fits_two_bundles(std::size_t payload_bytes) const;
    /// ...and two full bundles from `start` leave before its `deadline`.
    bool arrives_in_two_bundles(base::SteadyTime deadline, base::SteadyTime start, const LinkBudget& budget) const;

    /// `n` bytes of `whole` from `info.offset` on, as a sample of its own that a bundle carries as an entry.
    static Sample chunk_of(const Sample& whole, const Sample::Chunk& info, std::size_t n);
    /// A chunk smaller than this, but for a sample's last, is not worth its entry's header.
    static constexpr std::size_t MIN_CHUNK_BYTES = 64;

  private:
    /// The wire bits of a bundle `encoded_bytes` long.
    std::uint64_t bundle_bits(std::size_t encoded_bytes) const { return BundleBuilder(wire_).wire_bits(encoded_bytes); }

    WireModel wire_;
    BundleLimits limits_;
    base::Duration link_latency_;
};

}  // namespace tgw::core
