#include "gateway/dds/wan_setup.hpp"

#include <iostream>
#include <string>
#include <utility>

#include "base/discovery_server.hpp"
#include "gateway/dds/peer_lookup.hpp"

namespace tgw::dds {

std::vector<base::WanPeer> wan_peers_of(const GatewayConfig& config) {
    std::vector<base::WanPeer> peers;
    for (const std::string& text : config.wan_peers) {
        peers.push_back(base::parse_wan_peer(text, config.wan_domain));
    }
    peers = base::resolve_peer_names(std::move(peers));
    for (const base::WanPeer& peer : peers) {
        if (!peer.host.empty()) {
            std::cerr << "telemetry-gateway: --wan-peer " << peer.host << ": "
                      << (peer.address.empty() ? "does not resolve yet" : peer.address) << "; looked up again every "
                      << PeerLookup::PERIOD.count() << " s\n";
        }
    }
    return peers;
}

WanConfig wan_config_for(GatewayConfig& config, std::optional<base::SecurityFiles> security,
                         const std::vector<base::WanPeer>& peers) {
    WanConfig wan;
    wan.domain = config.wan_domain;
    wan.security = std::move(security);
    wan.peers = base::announcement_peers(peers, config.wan_domain, config.wan_peer_participants);
    if (!config.wan_interface.empty()) {
        wan.interface_address = base::initial_wan_address(config.wan_interface);
    }
    wan.listen_port = config.wan_port;
    if (!config.wan_discovery_server.empty()) {
        wan.discovery_server = base::parse_discovery_server(config.wan_discovery_server, "--wan-discovery-server");
    }
    wan.lease_duration = config.wan_lease;
    wan.announcement_period = config.wan_announcement_period;
    wan.max_datagram_bytes = config.scheduler.wire.max_datagram_bytes;
    wan.coalesce_window = config.wan_coalesce_window;
    wan.heartbeat_spacing_bytes = config.wan_heartbeat_bytes;
    wan.datagram_transport = config.wan_datagram_transport;
    core::WireModel& wire = config.scheduler.wire;
    if (config.compact_wan) {
        // Only the relay reads this participant's samples, and nothing at all reads the statistics submessage:
        // 60 bytes less in every datagram, bundles and discovery alike.
        wan.strip_statistics = true;
        wire = wire.without_statistics();
        if (!wan.security) {
            // ... and, in a message to the relay alone, the 16 bytes that name it (security signs them), and a
            // bundle's INFO_TS, 12 bytes: the bundle holds its write time. Only bundles are scheduled here.
            wan.strip_destination = true;
            wan.strip_timestamp = true;
            wire = wire.without_destination().without_timestamp();
        }
    }
    if (wan.security) {
        // Every message signed, every sample's submessages and payload encrypted (WireModel::with_security).
        wire = wire.with_security();
    }
    // Standard mode: a reliable reader's repair of a sample waits for the schedule, in that sample's urgency
    // (RepairDesk). Compact mode's bundles are charged as they are repaired, as before.
    wan.schedule_repairs = !config.compact_wan;
    // ... and so does a large sample's every fragment after its first (not readable under security's protection).
    config.scheduler.paced_fragments = !config.compact_wan && !wan.security;
    // Both modes: the participant's periodic announcements, a copy to each base-camp port, one at a time in the
    // schedule rather than all at once.
    wan.schedule_announcements = true;
    return wan;
}

}  // namespace tgw::dds
