// The robot's topics from a publisher's discovery to their retirement: bridges made, lanes and topics retired,
// what is left of them counted.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "base/clock.hpp"
#include "base/event_loop.hpp"
#include "core/forwarding_loop.hpp"
#include "gateway/dds/gateway_config.hpp"
#include "gateway/dds/repair_desk.hpp"
#include "gateway/dds/topic_accounting.hpp"
#include "gateway/dds/topic_bridge.hpp"
#include "gateway/dds/topic_filter.hpp"
#include "passthrough/discovery.hpp"
#include "passthrough/ttl_resolver.hpp"
#include "types/type_library.hpp"

namespace tgw::dds {

class CompactWan;
class RobotParticipant;
class TopicTable;
class WanRouter;

/// One TopicBridge per admitted topic, with a lane per QoS its publishers offer. Publishers discovered together
/// are bridged most urgent first. A lane whose last publisher left is retired a TTL later (plus LANE_LINGER), so
/// base-camp readers see its writer go, unless it was declared in the --qos file. A topic whose last lane was
/// retired is retired too once nothing of it is queued: its bridge, its scheduler slot and WAN topic go, and its
/// counts are kept by name (RetiredTopics), so that topics that come and go cost no memory for good. A publisher that
/// comes back gets a new bridge. Functions ending in _nts run in the worker loop only, where DDS entities are made
/// and deleted; the others from any thread.
class TopicLifecycle {
  public:
    /// What the topics are bridged between and with. The robot participant comes later (set_robot).
    struct Ends {
        WanRouter& wan;
        core::ForwardingLoop& loop;
        TopicTable& table;
        base::EventLoop& worker;
        const base::Clock& clock;
        CompactWan* compact = nullptr;  ///< compact WAN mode; null: standard
    };
    /// `config`, `filter` and `types` outlive it.
    TopicLifecycle(const GatewayConfig& config, const TopicFilter& filter, const types::TypeLibrary& types, Ends ends);

    /// The robot participant bridges read from; before the worker loop runs anything of this.
    void set_robot(RobotParticipant& robot) { robot_ = &robot; }

    /// A publisher discovered: bridged with those found within DISCOVERY_GATHERING of the first, most urgent first
    /// (bridge_gathered_nts).
    void gather_nts(passthrough::DiscoveredPublisher&& pub);
    /// Bridges `pub`'s topic, or finds or makes its lane; `declared`: from a --qos profile, no publisher yet.
    void bridge_nts(const passthrough::DiscoveredPublisher& pub, bool declared = false);
    /// A publisher left: if it was its lane's last, the lane is retired once its queued samples are past.
    void forget_writer_nts(const std::string& topic, const eprosima::fastrtps::rtps::GUID_t& writer);
    /// Tells the loop whether anyone at the base camp reads topic `id` (`reaches`), when that changed.
    void set_reachable_nts(core::TopicId id, bool reaches);
    /// set_reachable_nts for every bridged topic.
    void poll_reachability_nts();

    /// `topic`'s TTL: its rule's, a --qos profile's named after it, `publisher_lifespan`, --default-ttl.
    passthrough::ResolvedTtl ttl_for(const std::string& topic, std::optional<base::Duration> publisher_lifespan) const;
    /// Per topic name, what became of its samples, over every bridge it had: the topics bridged now, by name, then
    /// the retired ones, by name.
    std::vector<TopicCount> topic_counts() const;
    /// The robot's samples forwarded so far, retired topics' included.
    std::uint64_t forwarded() const;
    /// The bridged topic of WAN name `wan_topic`, for the RepairDesk's writer announcements.
    std::optional<RepairDesk::ScheduledTopic> scheduled_topic(std::string_view wan_topic) const;
    /// Lanes Fast DDS refused to make (see Gateway::refused_lanes).
    std::uint64_t refused_lanes() const { return refused_lanes_.load(); }

    /// How long a lane whose last publisher left outlives the TTL of its samples still queued.
    static constexpr std::chrono::seconds LANE_LINGER{1};
    /// Publishers discovered within this of the first of them are bridged together, most urgent first.
    static constexpr std::chrono::milliseconds DISCOVERY_GATHERING{20};
    /// A topic whose last lane was retired with samples still queued (their deadline later than its TTL from
    /// then: a source clock ahead) is looked at again this often, until they are sent or logged.
    static constexpr std::chrono::seconds RETIRE_RETRY{1};

  private:
    /// Bridges the publishers gathered, shortest TTL first: a new WAN writer's announcement (SEDP) crosses the link
    /// at once, and a base camp hears of it, matches and takes its samples only after. A robot program's
    /// publishers come together, in any order: bridged in the order found, the announcements of a picture's and a
    /// log's writers went ahead of the hazard's, and the hazard's first sample waited for a match past its deadline.
    void bridge_gathered_nts();
    /// Retires the lane, then the topic if that was its last lane (retire_topic_nts).
    void retire_lane_nts(const std::weak_ptr<TopicBridge>& bridge, std::uint16_t lane);
    /// Retires an idle bridge's topic once nothing of it is queued (else looks again after RETIRE_RETRY): the bridge
    /// leaves the table, its scheduler slot is freed and its counts are kept by name.
    void retire_topic_nts(const std::weak_ptr<TopicBridge>& bridge);
    /// The scheduler slot for a new topic: in compact mode the one its name had before, if any (its catalog
    /// entry says so already), else a free or new one. It starts unreachable.
    core::TopicId add_topic_nts(const core::TopicConfig& topic);
    /// For a keyed topic whose type `types_` declares: what computes the key hashes its publishers do not send.
    std::shared_ptr<const types::KeyHasher> key_hasher_for(const passthrough::DiscoveredPublisher& pub) const;

    const GatewayConfig& config_;
    const TopicFilter& filter_;
    const types::TypeLibrary& types_;
    Ends ends_;
    RobotParticipant* robot_ = nullptr;
    std::atomic<std::uint64_t> refused_lanes_{0};
    std::vector<passthrough::DiscoveredPublisher> gathered_;  ///< publishers discovered, to be bridged (gather_nts)
    std::vector<signed char> reachable_;                      ///< per topic, as last told to the loop; -1: not yet
    /// Compact WAN mode: the scheduler slot (the catalog's topic id) of each topic ever bridged and now retired,
    /// taken again by the same name only, so that an id in the catalog never changes its topic. The worker only.
    std::map<std::string, core::TopicId> compact_slots_;
    /// Held while a topic is retired and while the counts are read, so that a topic's counts are never seen in
    /// both its slot and its record, nor in neither.
    mutable std::mutex retired_mutex_;
    RetiredTopics retired_;  // under retired_mutex_
    /// The bridged topics by their names on the WAN.
    mutable std::mutex wan_topics_mutex_;
    std::unordered_map<std::string, RepairDesk::ScheduledTopic> wan_topics_;  // under wan_topics_mutex_
};

}  // namespace tgw::dds
