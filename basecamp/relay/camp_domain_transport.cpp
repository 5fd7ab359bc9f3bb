#include "basecamp/relay/camp_domain_transport.hpp"

#include <algorithm>
#include <memory>

#include "base/config_error.hpp"
#include "base/discovery_server.hpp"
#include "base/host_transport.hpp"

namespace tgw::basecamp {

std::vector<std::string> camp_addresses_off_the_wan(const std::vector<base::InterfaceAddress>& host,
                                                    const std::string& wan_address) {
    if (base::is_loopback_ipv4(wan_address))
        return {};
    const auto wan = std::find_if(host.begin(), host.end(),
                                  [&](const base::InterfaceAddress& each) { return each.address == wan_address; });
    if (wan == host.end())
        return {};
    std::vector<std::string> kept;
    for (const base::InterfaceAddress& each : host) {
        if (each.interface != wan->interface)
            kept.push_back(each.address);
    }
    return kept;
}

std::optional<std::string> wan_local_address(const base::PeerTransport& wan) {
    if (!wan.interface.empty())
        return base::resolve_ipv4(wan.interface, wan.interface_flag);
    if (!wan.peers.empty())
        return base::route_source_address(base::resolve_peers(wan).front());
    if (!wan.discovery_server.empty())
        return base::route_source_address(
            base::parse_discovery_server(wan.discovery_server, wan.discovery_server_flag).address);
    return std::nullopt;
}

std::vector<std::string> apply_camp_domain_transport(eprosima::fastdds::dds::DomainParticipantQos& qos,
                                                     const base::PeerTransport& local, const base::PeerTransport& wan,
                                                     int domain) {
    std::vector<std::string> kept;
    if (!local.interface.empty()) {
        kept = {base::resolve_ipv4(local.interface, local.interface_flag)};
    } else {
        const auto wan_address = wan_local_address(wan);
        const auto host = base::interface_addresses();
        if (wan_address && host)
            kept = camp_addresses_off_the_wan(*host, *wan_address);
    }
    // A whitelist is checked once, against the interfaces running at start: a camp LAN that comes up later is
    // not used (--local-interface, or a restart). Loopback is always running.
    base::apply_host_transport(qos, domain, {kept});
    return kept;
}

std::string describe_camp_domain(const std::vector<std::string>& addresses, const base::PeerTransport& local,
                                 const base::PeerTransport& wan) {
    if (addresses.empty())
        return "the camp's domain on every interface";
    std::string text = "the camp's domain on ";
    for (std::size_t i = 0; i < addresses.size(); ++i)
        text += (i > 0 ? ", " : "") + addresses[i];
    if (!local.interface.empty())
        return text + " (" + local.interface_flag + ")";
    return text + " (kept off the WAN's " + wan_local_address(wan).value_or("address") + ")";
}

}  // namespace tgw::basecamp
