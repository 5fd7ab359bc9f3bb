#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "base/time.hpp"
#include "core/drop_reason.hpp"

namespace tgw::core {

/// What happened to one topic's samples. Invariant: received == forwarded + queued + sum(dropped).
struct TopicCounters {
    std::uint64_t received = 0;
    std::uint64_t forwarded = 0;
    std::uint64_t queued = 0;
    std::uint64_t queued_payload_bytes = 0;  ///< of the samples queued now
    std::array<std::uint64_t, DROP_REASON_COUNT> dropped{};
    std::uint64_t forwarded_payload_bytes = 0;
    std::uint64_t forwarded_wire_bytes = 0;
    /// When its first sample arrived; nullopt before one did.
    std::optional<base::SteadyTime> first_received;

    std::uint64_t dropped_total() const {
        std::uint64_t n = 0;
        for (auto d : dropped)
            n += d;
        return n;
    }
    std::uint64_t& dropped_for(DropReason r) { return dropped[static_cast<std::size_t>(r)]; }
    std::uint64_t dropped_for(DropReason r) const { return dropped[static_cast<std::size_t>(r)]; }
    bool balanced() const { return received == forwarded + queued + dropped_total(); }

    TopicCounters& operator+=(const TopicCounters& o) {
        received += o.received;
        forwarded += o.forwarded;
        queued += o.queued;
        queued_payload_bytes += o.queued_payload_bytes;
        for (std::size_t i = 0; i < dropped.size(); ++i)
            dropped[i] += o.dropped[i];
        forwarded_payload_bytes += o.forwarded_payload_bytes;
        forwarded_wire_bytes += o.forwarded_wire_bytes;
        if (o.first_received && (!first_received || *o.first_received < *first_received))
            first_received = o.first_received;
        return *this;
    }
};

}  // namespace tgw::core
