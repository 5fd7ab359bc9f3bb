#include "gateway/dds/topic_lifecycle.hpp"

#include <algorithm>
#include <iostream>
#include <utility>

#include "base/robot_namespace.hpp"
#include "gateway/dds/robot_participant.hpp"
#include "gateway/dds/topic_table.hpp"
#include "gateway/dds/wan_router.hpp"
#include "passthrough/dds_time.hpp"

namespace tgw::dds {

TopicLifecycle::TopicLifecycle(const GatewayConfig& config, const TopicFilter& filter, const types::TypeLibrary& types,
                               Ends ends)
    : config_(config), filter_(filter), types_(types), ends_(ends) {}

void TopicLifecycle::forget_writer_nts(const std::string& topic, const eprosima::fastrtps::rtps::GUID_t& writer) {
    // Gone before it was bridged: it gets no lane, which would wait for it for ever.
    gathered_.erase(std::remove_if(gathered_.begin(), gathered_.end(),
                                   [&](const passthrough::DiscoveredPublisher& pub) { return pub.writer == writer; }),
                    gathered_.end());
    const std::shared_ptr<TopicBridge> bridge = ends_.table.find(topic);
    const std::optional<std::uint16_t> lane = bridge != nullptr ? bridge->release(writer) : std::nullopt;
    if (!lane) {
        return;
    }
    // What the publisher sent is still the base camp's due: the lane stays until its queued samples are past
    // their TTL. A publisher of the same offer that comes back meanwhile keeps it.
    const auto ttl = std::chrono::duration_cast<std::chrono::steady_clock::duration>(bridge->ttl().ttl);
    ends_.worker.post_at(
        std::chrono::steady_clock::now() + ttl + LANE_LINGER,
        [this, weak = std::weak_ptr<TopicBridge>(bridge), lane = *lane] { retire_lane_nts(weak, lane); });
}

void TopicLifecycle::retire_lane_nts(const std::weak_ptr<TopicBridge>& weak, std::uint16_t lane) {
    if (const std::shared_ptr<TopicBridge> bridge = weak.lock()) {
        bridge->retire(lane);
        retire_topic_nts(weak);
    }
}

void TopicLifecycle::retire_topic_nts(const std::weak_ptr<TopicBridge>& weak) {
    const std::shared_ptr<TopicBridge> bridge = weak.lock();
    // A publisher that came back meanwhile has a lane again; a bridge already retired is no longer in the table.
    if (bridge == nullptr || !bridge->idle() || ends_.table.find(bridge->name()) != bridge) {
        return;
    }
    bool retired = false;
    {
        std::lock_guard<std::mutex> lock(retired_mutex_);
        // In compact mode the slot is the topic's id in the catalog, whose entry stays on the WAN (see
        // compact_slots_): only the same name takes it again.
        const std::optional<core::TopicCounters> counts =
            ends_.loop.retire_topic(bridge->id(), ends_.compact == nullptr);
        if (counts) {
            ends_.table.remove(bridge->name());
            std::lock_guard<std::mutex> topics_lock(wan_topics_mutex_);
            wan_topics_.erase(bridge->wan_name());
            retired_.keep(bridge->name(), bridge->ttl(), *counts);
            if (ends_.compact) {
                compact_slots_[bridge->name()] = bridge->id();
            }
            retired = true;
        }
    }
    if (!retired) {
        // Its readers are gone, so nothing more comes; what is queued is sent or logged by its deadline.
        ends_.worker.post_at(std::chrono::steady_clock::now() + RETIRE_RETRY, [this, weak] { retire_topic_nts(weak); });
        return;
    }
    if (bridge->id() < reachable_.size()) {
        reachable_[bridge->id()] = -1;
    }
    // The bridge, its listeners and its WAN writers go here, or after a write that holds the bridge now.
}

core::TopicId TopicLifecycle::add_topic_nts(const core::TopicConfig& topic) {
    core::TopicId id = 0;
    const auto kept = compact_slots_.find(topic.name);
    if (kept != compact_slots_.end() && ends_.loop.add_topic_at(kept->second, topic)) {
        id = kept->second;
    } else {
        id = ends_.loop.add_topic(topic);
    }
    // Held until a base-camp reader matches its WAN writer, which takes discovery a moment at least.
    ends_.loop.set_reachable(id, false);
    if (id >= reachable_.size()) {
        reachable_.resize(static_cast<std::size_t>(id) + 1, -1);
    }
    reachable_[id] = 0;
    return id;
}

void TopicLifecycle::gather_nts(passthrough::DiscoveredPublisher&& pub) {
    gathered_.push_back(std::move(pub));
    if (gathered_.size() == 1) {
        ends_.worker.post_at(std::chrono::steady_clock::now() + DISCOVERY_GATHERING, [this] { bridge_gathered_nts(); });
    }
}

void TopicLifecycle::bridge_gathered_nts() {
    std::vector<std::pair<base::Duration, passthrough::DiscoveredPublisher>> by_ttl;
    by_ttl.reserve(gathered_.size());
    for (passthrough::DiscoveredPublisher& pub : gathered_) {
        const base::Duration ttl = ttl_for(pub.topic, pub.lifespan).ttl;
        by_ttl.emplace_back(ttl, std::move(pub));
    }
    gathered_.clear();
    std::stable_sort(by_ttl.begin(), by_ttl.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [ttl, pub] : by_ttl) {
        bridge_nts(pub);
    }
}

passthrough::ResolvedTtl TopicLifecycle::ttl_for(const std::string& topic,
                                                 std::optional<base::Duration> publisher_lifespan) const {
    std::optional<base::Duration> rule_ttl;
    if (const TopicRule* rule = config_.topic_rules.rule_for(topic)) {
        rule_ttl = rule->ttl;
    }
    std::optional<base::Duration> profile_lifespan;
    if (auto profile = ends_.wan.writer_profile(topic)) {
        profile_lifespan = passthrough::to_duration(profile->lifespan().duration);
    }
    return passthrough::resolve_ttl(rule_ttl, profile_lifespan, publisher_lifespan, config_.default_ttl);
}

void TopicLifecycle::bridge_nts(const passthrough::DiscoveredPublisher& pub, bool declared) {
    // The worker starts after set_robot, and the Gateway stops it before its robot participant goes.
    if (!filter_.admits(pub.topic)) {
        return;
    }
    if (const std::shared_ptr<TopicBridge> bridge = ends_.table.find(pub.topic)) {
        if (!bridge->admit(pub, declared)) {
            refused_lanes_.fetch_add(1, std::memory_order_relaxed);
        }
        return;
    }
    const passthrough::ResolvedTtl ttl = ttl_for(pub.topic, pub.lifespan);
    core::TopicConfig topic{pub.topic, ttl.ttl};
    if (const TopicRule* rule = config_.topic_rules.rule_for(pub.topic)) {
        topic.max_rate_hz = rule->max_rate_hz;
        topic.latest_only = rule->latest_only;
    }
    const core::TopicId id = add_topic_nts(topic);
    const std::string wan_name = base::namespaced_topic(config_.robot_name, pub.topic);
    {
        // Its WAN writers' announcements go in its urgency (RepairDesk::hold_writer_announcement).
        std::lock_guard<std::mutex> lock(wan_topics_mutex_);
        wan_topics_[wan_name] = RepairDesk::ScheduledTopic{id, ttl.ttl};
    }
    auto bridge = std::make_shared<TopicBridge>(
        id, pub.topic, wan_name, pub.type_name, pub.keyed, ttl,
        TopicBridge::Ends{*robot_, ends_.wan, ends_.loop, ends_.clock, ends_.compact}, key_hasher_for(pub));
    if (bridge->admit(pub, declared)) {
        ends_.table.add(std::move(bridge));
        return;
    }
    {
        std::lock_guard<std::mutex> lock(wan_topics_mutex_);
        wan_topics_.erase(wan_name);
    }
    // Fast DDS refused the WAN writer or the robot reader (admit logged which): nothing of the topic stays, so that
    // the next publisher of it gets one bridge, made afresh. No reader was made, so nothing of it is queued.
    refused_lanes_.fetch_add(1, std::memory_order_relaxed);
    std::lock_guard<std::mutex> lock(retired_mutex_);
    ends_.loop.retire_topic(id, ends_.compact == nullptr);
    if (ends_.compact) {
        compact_slots_[pub.topic] = id;  // its catalog entry may have been written
    }
}

std::shared_ptr<const types::KeyHasher> TopicLifecycle::key_hasher_for(
    const passthrough::DiscoveredPublisher& pub) const {
    if (!pub.keyed || types_.find(pub.type_name) == nullptr) {
        return nullptr;
    }
    std::string why;
    std::optional<types::KeyHasher> hasher = types::KeyHasher::for_type(types_, pub.type_name, why);
    if (!hasher) {
        std::cerr << "telemetry-gateway: " << pub.topic << ": its IDL gives no key hash (" << why
                  << "); a publisher that sends none has its samples kept as one instance\n";
        return nullptr;
    }
    return std::make_shared<const types::KeyHasher>(std::move(*hasher));
}

std::vector<TopicCount> TopicLifecycle::topic_counts() const {
    std::lock_guard<std::mutex> lock(retired_mutex_);
    std::vector<TopicCount> bridged;
    for (const std::shared_ptr<TopicBridge>& bridge : ends_.table.all()) {
        bridged.push_back(TopicCount{bridge->name(), bridge->ttl(), ends_.loop.counters(bridge->id()), true,
                                     bridge->matched_readers()});
    }
    return retired_.with(std::move(bridged));
}

void TopicLifecycle::set_reachable_nts(core::TopicId id, bool reaches) {
    if (id >= reachable_.size()) {
        reachable_.resize(static_cast<std::size_t>(id) + 1, -1);
    }
    const signed char now = reaches ? 1 : 0;
    if (reachable_[id] != now) {
        reachable_[id] = now;
        ends_.loop.set_reachable(id, now == 1);
    }
}

void TopicLifecycle::poll_reachability_nts() {
    for (const std::shared_ptr<TopicBridge>& bridge : ends_.table.all()) {
        set_reachable_nts(bridge->id(), bridge->reaches_anyone());
    }
}

std::uint64_t TopicLifecycle::forwarded() const {
    std::lock_guard<std::mutex> lock(retired_mutex_);
    std::uint64_t forwarded = retired_.total().forwarded;
    for (const std::shared_ptr<TopicBridge>& bridge : ends_.table.all()) {
        forwarded += ends_.loop.counters(bridge->id()).forwarded;
    }
    return forwarded;
}

std::optional<RepairDesk::ScheduledTopic> TopicLifecycle::scheduled_topic(std::string_view wan_topic) const {
    std::lock_guard<std::mutex> lock(wan_topics_mutex_);
    const auto it = wan_topics_.find(std::string(wan_topic));
    return it != wan_topics_.end() ? std::optional(it->second) : std::nullopt;
}

}  // namespace tgw::dds
