#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "base/time.hpp"

namespace tgw::core {

/// Counts latencies in fixed log-linear buckets (16 per power of two of nanoseconds, so any percentile is
/// known to within 1/32 of its value) and answers percentiles. record() is lock-free and allocation-free, cheap
/// enough for the per-sample path; any thread may call it and snapshot() at once.
class LatencyHistogram {
  public:
    /// Sub-buckets per power of two: 2^SUB_BUCKET_BITS. Values below 2^SUB_BUCKET_BITS ns are counted exactly.
    static constexpr unsigned SUB_BUCKET_BITS = 4;
    static constexpr std::size_t SUB_BUCKETS = std::size_t{1} << SUB_BUCKET_BITS;
    /// Enough buckets for every 64-bit nanosecond count.
    static constexpr std::size_t BUCKET_COUNT = (64 - SUB_BUCKET_BITS + 1) * SUB_BUCKETS;

    /// A copy of the counts at one moment. Records that run concurrently with snapshot() may be half in it
    /// (counted in a bucket but not yet in the sum), never lost.
    struct Snapshot {
        std::vector<std::uint64_t> buckets;  ///< BUCKET_COUNT counts, or empty when nothing was recorded
        std::uint64_t count = 0;
        base::Duration sum{0};
        /// Exact in a snapshot(); in one made by since(), the top of the highest bucket used (within resolution).
        base::Duration max{0};

        /// The latency below or at which a fraction `q` (0 to 1) of the samples fall, as the midpoint of its
        /// bucket and never above max (percentile(1) is max); zero when empty.
        base::Duration percentile(double q) const;
        base::Duration median() const { return percentile(0.5); }
        /// Zero when empty.
        base::Duration mean() const;
        /// What was recorded after `earlier` (a snapshot of the same histogram), for leaving a warm-up out.
        Snapshot since(const Snapshot& earlier) const;
    };

    /// Counts one latency; a negative one (a clock stepped back) counts as zero.
    void record(base::Duration latency) noexcept;
    Snapshot snapshot() const;

    /// The bucket a value in nanoseconds falls in, and that bucket's bounds [lower, upper).
    static std::size_t bucket_of(std::uint64_t ns) noexcept;
    static std::uint64_t bucket_lower_ns(std::size_t bucket) noexcept;
    /// One past the bucket's largest value; saturates at UINT64_MAX for the last bucket.
    static std::uint64_t bucket_upper_ns(std::size_t bucket) noexcept;

  private:
    std::array<std::atomic<std::uint64_t>, BUCKET_COUNT> buckets_{};
    std::atomic<std::int64_t> sum_ns_{0};
    std::atomic<std::int64_t> max_ns_{0};
};

}  // namespace tgw::core
