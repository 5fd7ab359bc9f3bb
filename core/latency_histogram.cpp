#include "core/latency_histogram.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tgw::core {

namespace {

unsigned msb_of(std::uint64_t v) {
    return 63u - static_cast<unsigned>(__builtin_clzll(v));
}

}  // namespace

std::size_t LatencyHistogram::bucket_of(std::uint64_t ns) noexcept {
    if (ns < SUB_BUCKETS) {
        return static_cast<std::size_t>(ns);
    }
    // The top SUB_BUCKET_BITS + 1 bits of the value: the power of two picks the row, the next bits the column.
    const unsigned msb = msb_of(ns);
    const unsigned shift = msb - SUB_BUCKET_BITS;
    const std::size_t sub = static_cast<std::size_t>(ns >> shift) & (SUB_BUCKETS - 1);
    return (shift + 1) * SUB_BUCKETS + sub;
}

std::uint64_t LatencyHistogram::bucket_lower_ns(std::size_t bucket) noexcept {
    if (bucket < SUB_BUCKETS) {
        return bucket;
    }
    const std::size_t shift = bucket / SUB_BUCKETS - 1;
    const std::uint64_t sub = bucket % SUB_BUCKETS;
    return (SUB_BUCKETS + sub) << shift;
}

std::uint64_t LatencyHistogram::bucket_upper_ns(std::size_t bucket) noexcept {
    if (bucket + 1 >= BUCKET_COUNT) {
        return std::numeric_limits<std::uint64_t>::max();
    }
    return bucket_lower_ns(bucket + 1);
}

void LatencyHistogram::record(base::Duration latency) noexcept {
    const std::int64_t ns = std::max<std::int64_t>(latency.count(), 0);
    buckets_[bucket_of(static_cast<std::uint64_t>(ns))].fetch_add(1, std::memory_order_relaxed);
    sum_ns_.fetch_add(ns, std::memory_order_relaxed);
    std::int64_t seen = max_ns_.load(std::memory_order_relaxed);
    while (ns > seen && !max_ns_.compare_exchange_weak(seen, ns, std::memory_order_relaxed)) {
    }
}

LatencyHistogram::Snapshot LatencyHistogram::snapshot() const {
    Snapshot s;
    s.buckets.resize(BUCKET_COUNT);
    for (std::size_t i = 0; i < BUCKET_COUNT; ++i) {
        s.buckets[i] = buckets_[i].load(std::memory_order_relaxed);
        s.count += s.buckets[i];
    }
    s.sum = base::Duration(sum_ns_.load(std::memory_order_relaxed));
    s.max = base::Duration(max_ns_.load(std::memory_order_relaxed));
    if (s.count == 0) {
        s.buckets.clear();
    }
    return s;
}

base::Duration LatencyHistogram::Snapshot::percentile(double q) const {
    if (count == 0) {
        return base::Duration::zero();
    }
    // Nearest rank: the smallest value with at least q * count samples at or below it.
    const double clamped = std::clamp(q, 0.0, 1.0);
    const auto rank = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(clamped * count)));
    if (rank >= count) {
        return max;  // the largest sample is known exactly
    }
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < buckets.size(); ++i) {
        seen += buckets[i];
        if (seen >= rank) {
            const std::uint64_t lower = bucket_lower_ns(i);
            const std::uint64_t upper = bucket_upper_ns(i);
            const std::uint64_t mid = lower + (upper - lower - 1) / 2;
            return std::min(base::Duration(static_cast<std::int64_t>(std::min<std::uint64_t>(
                                mid, static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())))),
                            max);
        }
    }
    return max;
}

base::Duration LatencyHistogram::Snapshot::mean() const {
    return count == 0 ? base::Duration::zero() : base::Duration(sum.count() / static_cast<std::int64_t>(count));
}

LatencyHistogram::Snapshot LatencyHistogram::Snapshot::since(const Snapshot& earlier) const {
    Snapshot s;
    if (count == 0) {
        return s;
    }
    s.max = max;
    s.buckets = buckets;
    for (std::size_t i = 0; i < earlier.buckets.size() && i < s.buckets.size(); ++i) {
        s.buckets[i] -= std::min(s.buckets[i], earlier.buckets[i]);
    }
    for (std::uint64_t b : s.buckets) {
        s.count += b;
    }
    s.sum = sum - earlier.sum;
    if (s.count == 0) {
        s.buckets.clear();
        s.sum = base::Duration::zero();
        s.max = base::Duration::zero();
        return s;
    }
    // The exact maximum of the later records is unknown: take the top of the highest bucket they used.
    std::size_t top = s.buckets.size() - 1;
    while (s.buckets[top] == 0) {
        --top;
    }
    const std::uint64_t top_ns = bucket_upper_ns(top) - 1;
    if (top_ns < static_cast<std::uint64_t>(max.count())) {
        s.max = base::Duration(static_cast<std::int64_t>(top_ns));
    }
    return s;
}

}  // namespace tgw::core
