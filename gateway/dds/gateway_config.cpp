#include "gateway/dds/gateway_config.hpp"

#include "base/config_error.hpp"
#include "base/discovery_server.hpp"
#include "base/receive_buffer.hpp"
#include "base/robot_namespace.hpp"
#include "base/wan_address.hpp"
#include "gateway/dds/wan_router.hpp"
#include "passthrough/uplink_topics.hpp"

namespace tgw::dds {

namespace {

// Fast DDS accepts domain ids whose well-known ports fit in 16 bits.
constexpr int MAX_DOMAIN_ID = 232;

void check_domain(const char* flag, int domain) {
    if (domain < 0 || domain > MAX_DOMAIN_ID) {
        throw base::ConfigError(std::string(flag) + " " + std::to_string(domain) + ": must be 0 to " +
                                std::to_string(MAX_DOMAIN_ID));
    }
}

}  // namespace

void GatewayConfig::validate() const {
    check_domain("--robot-domain", robot_domain);
    check_domain("--wan-domain", wan_domain);
    if (!robot_name.empty()) {
        if (const std::string problem = base::robot_name_problem(robot_name); !problem.empty()) {
            throw base::ConfigError("--robot-name '" + robot_name + "': " + problem);
        }
    }
    if (backfill && log_file.empty()) {
        throw base::ConfigError("backfill needs the on-robot log, whose rows it sends (drop --no-log)");
    }
    if (backfill_max_bps > 0 && !backfill) {
        throw base::ConfigError("--backfill-max-bps: backfill is off (--no-log keeps no rows to send)");
    }
    if (robot_domain == wan_domain) {
        // One domain would make the gateway read its own WAN writers back.
        throw base::ConfigError("--wan-domain " + std::to_string(wan_domain) + ": must differ from --robot-domain");
    }
    const std::size_t datagram = scheduler.wire.max_datagram_bytes;
    if (datagram < core::WireModel::MIN_DATAGRAM_PAYLOAD_BYTES || datagram > core::WireModel::MAX_UDP_PAYLOAD_BYTES) {
        throw base::ConfigError("--wan-max-datagram " + std::to_string(datagram) + ": expected " +
                                std::to_string(core::WireModel::MIN_DATAGRAM_PAYLOAD_BYTES) + " to " +
                                std::to_string(core::WireModel::MAX_UDP_PAYLOAD_BYTES) + " bytes");
    }
    if (!wan_security.empty() && datagram < SECURE_MIN_DATAGRAM_BYTES) {
        throw base::ConfigError("--wan-max-datagram " + std::to_string(datagram) + ": with --wan-security at least " +
                                std::to_string(SECURE_MIN_DATAGRAM_BYTES) +
                                " bytes, or Fast DDS cannot send its authentication handshake");
    }
    if (robot.receive_buffer_bytes < base::MIN_RECEIVE_BUFFER_BYTES ||
        robot.receive_buffer_bytes > base::MAX_RECEIVE_BUFFER_BYTES) {
        throw base::ConfigError("--robot-receive-buffer " + std::to_string(robot.receive_buffer_bytes) + ": expected " +
                                std::to_string(base::MIN_RECEIVE_BUFFER_BYTES) + " to " +
                                std::to_string(base::MAX_RECEIVE_BUFFER_BYTES) + " bytes");
    }
    if (wan_coalesce_window < std::chrono::microseconds::zero() || wan_coalesce_window > MAX_COALESCE_WINDOW) {
        throw base::ConfigError("--wan-coalesce-us " + std::to_string(wan_coalesce_window.count()) +
                                ": expected 0 to " + std::to_string(MAX_COALESCE_WINDOW.count()) + " microseconds");
    }
    if (wan_peer_participants < 1 || wan_peer_participants > MAX_WAN_PEER_PARTICIPANTS) {
        throw base::ConfigError("--wan-peer-participants " + std::to_string(wan_peer_participants) +
                                ": expected 1 to " + std::to_string(MAX_WAN_PEER_PARTICIPANTS));
    }
    if (compact_wan && scheduler.policy != core::PolicyKind::ttl && scheduler.policy != core::PolicyKind::edf) {
        throw base::ConfigError("--wan-mode compact: bundles need --policy ttl or edf, not " +
                                std::string(core::to_string(scheduler.policy)));
    }
    if (wan_compress && !compact_wan) {
        throw base::ConfigError("--wan-compress: compresses bundles, so it needs --wan-mode compact");
    }
    if (default_ttl <= base::Duration::zero()) {
        throw base::ConfigError("--default-ttl: must be positive");
    }
    for (const std::string& peer : wan_peers) {
        base::parse_wan_peer(peer, wan_domain);
    }
    passthrough::UplinkTopics(uplink, robot_name);  // throws naming --uplink
    for (const auto* globs : {&allow, &deny}) {
        for (const std::string& glob : *globs) {
            if (glob.empty()) {
                throw base::ConfigError(std::string(globs == &allow ? "--allow" : "--deny") + ": empty glob");
            }
        }
    }
    if (!wan_discovery_server.empty()) {
        base::parse_discovery_server(wan_discovery_server, "--wan-discovery-server");
        if (!wan_peers.empty()) {
            throw base::ConfigError(
                "--wan-discovery-server excludes --wan-peer: the server tells the gateway of the "
                "base camp's participants");
        }
    } else if (wan_peers.empty()) {
        // The WAN participant announces itself only to its peers (multicast costs the radio and rarely crosses
        // it), so without one no base camp would ever hear of this gateway, and it would run sending nothing.
        throw base::ConfigError(
            "--wan-peer: missing: give the base camp's host, IPv4[:PORT] (repeatable), or --wan-discovery-server "
            "ADDR:PORT; the gateway announces itself to no one else");
    }
}

}  // namespace tgw::dds
