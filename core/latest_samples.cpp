#include "core/latest_samples.hpp"

#include <utility>

namespace tgw::core {

std::size_t LatestSamples::InstanceHash::operator()(const Instance& instance) const {
    // FNV-1a over the topic and the key hash (itself an MD5 or the key's bytes: spread enough).
    std::uint64_t hash = 14695981039346656037ull;
    const auto mix = [&](std::uint8_t byte) { hash = (hash ^ byte) * 1099511628211ull; };
    for (int shift = 0; shift < 32; shift += 8)
        mix(static_cast<std::uint8_t>(instance.topic >> shift));
    for (const std::uint8_t byte : instance.key)
        mix(byte);
    return static_cast<std::size_t>(hash);
}

LatestSamples::Instance LatestSamples::instance_of(TopicId topic, const InstanceKey& key) {
    Instance instance{topic, {}};
    if (key.valid)
        instance.key = key.bytes;
    return instance;
}

std::optional<LatestSamples::Queued> LatestSamples::exchange(TopicId topic, const InstanceKey& key, Queued newer) {
    const auto [it, inserted] = queued_.try_emplace(instance_of(topic, key), newer);
    if (inserted)
        return std::nullopt;
    return std::exchange(it->second, newer);
}

void LatestSamples::forget_topic(TopicId topic) {
    for (auto it = queued_.begin(); it != queued_.end();) {
        it = it->first.topic == topic ? queued_.erase(it) : std::next(it);
    }
}

}  // namespace tgw::core
