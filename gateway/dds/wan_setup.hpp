// The WAN participant as the gateway's flags ask for it.
#pragma once

#include <optional>
#include <vector>

#include "base/security_files.hpp"
#include "base/wan_address.hpp"
#include "gateway/dds/gateway_config.hpp"
#include "gateway/dds/wan_router.hpp"

namespace tgw::dds {

/// --wan-peer, parsed and resolved; a host name that does not resolve yet is said on stderr (PeerLookup looks again).
std::vector<base::WanPeer> wan_peers_of(const GatewayConfig& config);

/// The WAN participant's configuration for `config`, announcing to `peers`, without the gateway's callbacks. What
/// the participant strips (compact mode) and adds (DDS Security) changes what a sample costs on the wire, so
/// `config.scheduler.wire` and `paced_fragments` are brought in line with it here, in one place.
WanConfig wan_config_for(GatewayConfig& config, std::optional<base::SecurityFiles> security,
                         const std::vector<base::WanPeer>& peers);

}  // namespace tgw::dds
