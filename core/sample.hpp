#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "base/time.hpp"

namespace tgw::core {

/// Index of a topic in the scheduler's topic table, dense from 0.
using TopicId = std::uint32_t;

/// The DDS instance a keyed sample belongs to (the RTPS key hash), opaque to the core.
struct InstanceKey {
    std::array<std::uint8_t, 16> bytes{};
    bool valid = false;
};

/// What a sample says about its instance. The core schedules each kind alike; a dispose or unregister carries
/// no payload (DDS instance lifecycle, passed through to the base camp).
enum class SampleKind : std::uint8_t { data, dispose, unregister };

/// "data", "dispose" or "unregister": the kind's name in the on-robot log.
constexpr std::string_view to_string(SampleKind kind) {
    switch (kind) {
        case SampleKind::dispose:
            return "dispose";
        case SampleKind::unregister:
            return "unregister";
        case SampleKind::data:
            break;
    }
    return "data";
}

/// The kind named `name` (to_string's), or nothing.
constexpr std::optional<SampleKind> sample_kind_named(std::string_view name) {
    for (const SampleKind kind : {SampleKind::data, SampleKind::dispose, SampleKind::unregister}) {
        if (to_string(kind) == name)
            return kind;
    }
    return std::nullopt;
}

/// One sample on its way from the robot domain to the WAN, as the core sees it: opaque bytes with times.
struct Sample {
    TopicId topic = 0;
    std::vector<std::uint8_t> payload;  ///< serialized data as received, encapsulation header included
    InstanceKey key;
    /// Which of the topic's outputs carries it (in the gateway: the WAN writer of the QoS its publisher
    /// offered); opaque to the core.
    std::uint16_t route = 0;
    SampleKind kind = SampleKind::data;
    base::WallTime source_time;  ///< the publisher's source timestamp
    base::SteadyTime arrival;    ///< set by the scheduler on push
    base::SteadyTime deadline;   ///< set by the scheduler on push: source (or arrival) time + the topic's TTL
    std::uint64_t sequence = 0;  ///< set by the scheduler on push: arrival order, breaks ties
    /// Compact WAN mode: set when the payload is a piece of a sample too large to leave in one bundle.
    struct Chunk {
        std::uint32_t id = 0;  ///< shared by the pieces of one sample
        std::uint32_t total_bytes = 0;
        std::uint32_t offset = 0;
    };
    std::optional<Chunk> chunk;
    /// False only for a chunk that is not the sample's last piece.
    bool completes_sample() const { return !chunk || chunk->offset + payload.size() >= chunk->total_bytes; }
};

}  // namespace tgw::core
