// The latest_only rule's memory: where each instance's waiting sample is, so that a newer one replaces it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <unordered_map>

#include "core/deadline_queue.hpp"
#include "core/sample.hpp"

namespace tgw::core {

/// For each instance of the latest_only topics (an unkeyed topic is one instance), the slot its last queued sample
/// took. An entry outlives its sample's stay in the queue (DeadlineQueue::holds tells), and stays until its topic
/// is forgotten: one entry per instance seen.
class LatestSamples {
  public:
    struct Queued {
        DeadlineQueue::Slot slot;
        std::uint64_t sequence;
    };

    /// Remembers `newer` as the latest sample of `topic` and `key`'s instance; returns the one it replaces there,
    /// if any.
    std::optional<Queued> exchange(TopicId topic, const InstanceKey& key, Queued newer);
    /// Forgets every instance of `topic`.
    void forget_topic(TopicId topic);

  private:
    struct Instance {
        TopicId topic;
        std::array<std::uint8_t, 16> key;
        bool operator==(const Instance& other) const { return topic == other.topic && key == other.key; }
    };
    struct InstanceHash {
        std::size_t operator()(const Instance& instance) const;
    };
    static Instance instance_of(TopicId topic, const InstanceKey& key);

    std::unordered_map<Instance, Queued, InstanceHash> queued_;
};

}  // namespace tgw::core
