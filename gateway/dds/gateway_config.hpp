// What the telemetry-gateway program's flags and configuration file set, and its checks.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <fastdds/rtps/transport/TransportDescriptorInterface.h>
#include "base/time.hpp"
#include "core/scheduler.hpp"
#include "gateway/dds/coalescing_transport.hpp"
#include "gateway/dds/datagram_coalescer.hpp"
#include "gateway/dds/robot_transport.hpp"
#include "gateway/dds/topic_rules.hpp"

namespace tgw::dds {

/// Everything the telemetry-gateway program's flags set (docs/design.md §6).
struct GatewayConfig {
    int robot_domain = 0;
    int wan_domain = 1;
    std::vector<std::string> wan_peers;  ///< ADDR or ADDR:PORT, see parse_wan_peer
    /// ADDR:PORT of a Fast DDS Discovery Server (--wan-discovery-server): discovery through it instead of
    /// announcements to wan_peers, which it excludes.
    std::string wan_discovery_server;
    /// A peer given without a port gets the announcements at the ports of this many participants (peer_ports).
    int wan_peer_participants = 4;
    static constexpr int MAX_WAN_PEER_PARTICIPANTS = 32;
    std::string wan_interface;   ///< interface name or IPv4 address; empty: every interface
    std::uint16_t wan_port = 0;  ///< own metatraffic port on the WAN; 0: Fast DDS's well-known port
    RobotTransport robot;
    std::string qos_file;  ///< Fast DDS XML; empty: none
    /// --idl: directories of IDL files; a keyed type found there gets its key hash computed from the payload
    /// when its publisher sends none (types::KeyHasher).
    std::vector<std::string> idl_dirs;
    std::string log_file;             ///< on-robot SQLite log; empty: none
    std::uint64_t log_max_bytes = 0;  ///< the log's cap (RobotLog); 0: none
    std::vector<std::string> allow;   ///< topic globs; empty: all
    std::vector<std::string> deny;
    /// The configuration file's `topics:` rules: a topic's first match sets its TTL, whether it is bridged (before
    /// allow and deny), its rate cap and latest_only. Their uplink topics are in `uplink` too.
    TopicRules topic_rules;
    /// --uplink: robot topics (by the robot's own names) the base camp may publish into the robot domain, each
    /// under its WAN name (base::namespaced_topic); empty: nothing flows from the WAN into the robot domain.
    std::vector<std::string> uplink;
    /// --duplex half: the radio carries both directions on one channel, so the uplink's bytes are charged to the
    /// budget as traffic outside the schedule (and told in the status: a base camp's grants leave room for them);
    /// false (full): they are only counted.
    bool uplink_shares_link = true;
    /// --robot-name: the robot's topics appear on the WAN under this name (base::namespaced_topic); empty: under
    /// their own names. Allow, deny and --qos profiles go by the robot's own names.
    std::string robot_name;
    base::Duration default_ttl = std::chrono::seconds(5);
    core::SchedulerConfig scheduler;
    /// Compact WAN mode (--wan-mode compact): what the scheduler releases together leaves as one bundle, and the
    /// base camp's relay unpacks it; needs a scheduler.bundles limit (set from the wire model when missing).
    bool compact_wan = false;
    /// Compact WAN mode: zstd-compress a bundle's entries where that makes it smaller (--wan-compress).
    bool wan_compress = false;
    /// An identity directory made by scripts/make-certs (--wan-security): DDS Security on the WAN participant only;
    /// empty: none. Its files are checked before the participant is created (base::SecurityFiles::load).
    std::string wan_security;
    std::chrono::seconds wan_lease{120};
    std::chrono::seconds wan_announcement_period{20};
    /// Read the base camp's receiver reports (tgw/receiver_report), see receiver_report().
    bool receiver_reports = false;
    /// --channel-grants: budget for the lower of the sensor's rate and the base camp's grant for this gateway
    /// (tgw/grant) while it is valid: a fleet's shared channel.
    bool channel_grants = false;
    /// WanConfig::coalesce_window: how long a WAN sample may wait to share a datagram; 0: never.
    std::chrono::microseconds wan_coalesce_window = DatagramCoalescer::DEFAULT_WINDOW;
    /// See WanConfig::datagram_transport.
    std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface> wan_datagram_transport;
    /// See WanConfig::heartbeat_spacing_bytes.
    std::uint32_t wan_heartbeat_bytes = DEFAULT_HEARTBEAT_SPACING_BYTES;
    static constexpr std::chrono::microseconds MAX_COALESCE_WINDOW{100'000};
    /// How often the gateway publishes its status (STATUS_TOPIC) at most; zero: never (telemetry-gateway's
    /// --status-period defaults to 1 s). On a slow link it comes less often, so that it takes at most
    /// STATUS_RATE_SHARE of the sensed rate.
    base::Duration status_period = base::Duration::zero();
    /// Backfill (docs/design/backfill.md): the on-robot log's rows cross to the base camp in capacity no live
    /// sample wants, until the camp acknowledges them. Needs a log. telemetry-gateway turns it on wherever it keeps
    /// one (--no-backfill).
    bool backfill = false;
    /// The most bit/s backfill may take (--backfill-max-bps); 0: only the budget bounds it.
    double backfill_max_bps = 0.0;

    /// Throws base::ConfigError naming the flag at fault. Checks what needs no file or network.
    void validate() const;
};

}  // namespace tgw::dds
