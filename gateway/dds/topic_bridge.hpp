#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "base/clock.hpp"
#include "core/forwarding_loop.hpp"
#include "core/sample.hpp"
#include "gateway/dds/wan_writer.hpp"
#include "passthrough/discovery.hpp"
#include "passthrough/lane_assignment.hpp"
#include "passthrough/offered_qos.hpp"
#include "passthrough/ttl_resolver.hpp"
#include "types/key_hash.hpp"

namespace eprosima::fastdds::dds {
class DataReader;
}

namespace tgw::dds {

class CompactWan;
class LaneListener;
class RobotParticipant;
class WanRouter;

/// What a bridged topic looks like from outside, copied at one instant.
struct BridgedTopic {
    core::TopicId id = 0;
    std::string name;
    std::string type_name;
    bool keyed = false;
    passthrough::ResolvedTtl ttl;
    /// The QoS offers of its publishers, one lane each (a robot reader and a WAN writer), by lane index.
    std::vector<passthrough::OfferedQos> lanes;
    /// By lane index: false once the lane's last publisher has left and the lane was retired (its index is
    /// reused by the next new offer).
    std::vector<bool> live;
};

/// One robot-domain topic the gateway bridges, and everything it has of it: its names, key kind and TTL, which
/// publisher goes through which lane (LaneAssignment), and per lane (one per QoS its publishers offer) the
/// type-agnostic robot reader that asks for that QoS, its listener, and the WAN writer that offers it. Its
/// queue and counters are the scheduler's, under the same TopicId (core knows no DDS). A new offer that no lane
/// matches gets a lane of its own, so a publisher never changes what the others' readers see; a lane whose last
/// publisher left is retired (unless it was declared in the --qos file) and its index reused.
///
/// The gateway's worker thread admits publishers, retires lanes and closes the readers; any thread may write
/// and ask.
class TopicBridge {
  public:
    /// What the bridge makes its lanes' entities with; each must outlive the bridge, and `robot` its readers.
    struct Ends {
        RobotParticipant& robot;
        WanRouter& wan;
        core::ForwardingLoop& loop;
        const base::Clock& clock;
        /// Compact WAN mode: lanes are announced in its catalog instead of getting WAN writers; null: standard.
        CompactWan* compact = nullptr;
    };

    /// `name` on the robot domain, `wan_name` on the WAN (GatewayConfig::robot_name).
    /// `key_hasher`: see LaneListener; null when the type's IDL is not known.
    TopicBridge(core::TopicId id, std::string name, std::string wan_name, std::string type_name, bool keyed,
                passthrough::ResolvedTtl ttl, Ends ends, std::shared_ptr<const types::KeyHasher> key_hasher = nullptr);
    /// Lets go of the WAN writers; close_readers() must have run.
    ~TopicBridge();

    TopicBridge(const TopicBridge&) = delete;
    TopicBridge& operator=(const TopicBridge&) = delete;

    core::TopicId id() const { return id_; }
    const std::string& name() const { return name_; }
    /// What the base camp calls it: `name`, under the robot's name when it has one.
    const std::string& wan_name() const { return wan_name_; }
    const std::string& type_name() const { return type_name_; }
    const passthrough::ResolvedTtl& ttl() const { return ttl_; }

    /// Carries `pub`'s samples from now on, on the lane of its offer, or on a new one; `declared`: a --qos
    /// profile's lane, made before any publisher, that takes any publisher its reader matches. False (after
    /// logging it) when Fast DDS refused a new lane's reader or writer. The worker thread only.
    bool admit(const passthrough::DiscoveredPublisher& pub, bool declared);
    /// A publisher left. Returns its lane when it was the lane's last publisher and the lane may be retired.
    std::optional<std::uint16_t> release(const eprosima::fastrtps::rtps::GUID_t& writer);
    /// Deletes the lane's robot reader and WAN writer, unless a publisher came back to it meanwhile; samples of
    /// it still queued then find no writer. The worker thread only.
    void retire(std::uint16_t lane);
    /// Deletes every robot reader: no sample comes in after this. The WAN writers stay.
    void close_readers();
    /// True when every lane was retired (or none was made): the bridge reads and writes nothing, and the gateway
    /// may retire the topic. A lane declared in the --qos file is never retired, so its topic is never idle.
    bool idle() const;

    /// Writes (or disposes, or unregisters) through the WAN writer of the sample's lane. Never throws.
    WriteResult write(core::Sample& sample, AfterWrite after = AfterWrite::payload_needed) const;

    /// Robot-domain writers matched now, all lanes together.
    std::int32_t matched_writers() const;
    /// Base-camp readers matched now, all lanes together.
    std::int32_t matched_readers() const;
    /// Whether a sample written now reaches anyone: a base-camp reader is matched, or a lane's WAN writer keeps
    /// its samples for readers that join later (transient local, standard mode).
    bool reaches_anyone() const;
    /// The Lifespan QoS of the lane's WAN writer; nullopt without a writer or when it is infinite.
    std::optional<base::Duration> writer_lifespan(std::uint16_t lane) const;
    BridgedTopic describe() const;

  private:
    struct Lane;

    std::optional<std::uint16_t> lane_for_nts(const passthrough::OfferedQos& offer) const;

    const core::TopicId id_;
    const std::string name_;
    const std::string wan_name_;
    const std::string type_name_;
    const bool keyed_;
    const passthrough::ResolvedTtl ttl_;
    Ends ends_;
    const std::shared_ptr<const types::KeyHasher> key_hasher_;
    passthrough::LaneAssignment writers_;  ///< before lanes_: their listeners read it
    mutable std::mutex mutex_;
    std::vector<Lane> lanes_;  // by lane index; only the worker thread adds or retires
};

}  // namespace tgw::dds
