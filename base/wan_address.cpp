#include "base/wan_address.hpp"

#include <net/if.h>

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>

#include <memory>

#include "base/config_error.hpp"
#include "base/interface_addresses.hpp"

namespace tgw::base {

namespace {

using base::is_ipv4;

using IfaddrsPtr = std::unique_ptr<ifaddrs, void (*)(ifaddrs*)>;

IfaddrsPtr list_interfaces(const std::string& name_or_address, const std::string& flag = "--wan-interface") {
    ifaddrs* list = nullptr;
    if (getifaddrs(&list) != 0) {
        throw base::ConfigError(flag + " '" + name_or_address + "': cannot list network interfaces");
    }
    return IfaddrsPtr(list, freeifaddrs);
}

std::string ipv4_text(const sockaddr* address) {
    char buf[INET_ADDRSTRLEN] = {};
    inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(address)->sin_addr, buf, sizeof buf);
    return buf;
}

bool has_ipv4(const ifaddrs* it) {
    return it->ifa_name != nullptr && it->ifa_addr != nullptr && it->ifa_addr->sa_family == AF_INET;
}

}  // namespace

WanPeer parse_wan_peer(const std::string& text, int domain) {
    WanPeer peer;
    const auto colon = text.rfind(':');
    peer.address = colon == std::string::npos ? text : text.substr(0, colon);
    if (!is_ipv4(peer.address)) {
        if (!base::is_host_name(peer.address)) {
            throw base::ConfigError("--wan-peer '" + text +
                                    "': expected an IPv4 address or a host name, optionally with :PORT");
        }
        peer.host = peer.address;
        peer.address.clear();
    }
    if (colon == std::string::npos) {
        peer.port = metatraffic_unicast_port(domain, 0);
        return peer;
    }
    const std::string port_text = text.substr(colon + 1);
    std::size_t used = 0;
    long port = 0;
    try {
        port = std::stol(port_text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != port_text.size() || port <= 0 || port > 65535) {
        throw base::ConfigError("--wan-peer '" + text + "': port must be a number from 1 to 65535");
    }
    peer.port = static_cast<std::uint16_t>(port);
    peer.exact_port = true;
    return peer;
}

std::vector<WanPeer> resolve_peer_names(std::vector<WanPeer> given) {
    for (WanPeer& peer : given) {
        if (!peer.host.empty()) {
            peer.address = base::lookup_ipv4(peer.host).value_or("");
        }
    }
    return given;
}

std::vector<WanPeer> announcement_peers(const std::vector<WanPeer>& peers, int domain, int participants) {
    std::vector<WanPeer> out;
    for (const WanPeer& peer : peers) {
        if (peer.address.empty()) {
            continue;
        }
        for (const std::uint16_t port : peer_ports(peer, domain, participants)) {
            out.push_back(WanPeer{peer.address, peer.host, port, true});
        }
    }
    return out;
}

std::vector<std::uint16_t> peer_ports(const WanPeer& peer, int domain, int participants) {
    if (peer.exact_port) {
        return {peer.port};
    }
    std::vector<std::uint16_t> ports;
    for (int id = 0; id < participants; ++id) {
        ports.push_back(metatraffic_unicast_port(domain, id));
    }
    return ports;
}

std::string resolve_interface_address(const std::string& name_or_address, const std::string& flag) {
    if (is_ipv4(name_or_address)) {
        return name_or_address;
    }
    const IfaddrsPtr list = list_interfaces(name_or_address, flag);
    bool exists = false;
    for (const ifaddrs* it = list.get(); it != nullptr; it = it->ifa_next) {
        if (it->ifa_name == nullptr || name_or_address != it->ifa_name) {
            continue;
        }
        exists = true;
        if (has_ipv4(it)) {
            return ipv4_text(it->ifa_addr);
        }
    }
    throw base::ConfigError(flag + " '" + name_or_address + "': " +
                            (exists ? "the interface has no IPv4 address" : "no such interface or IPv4 address"));
}

std::string initial_wan_address(const std::string& name_or_address) {
    if (is_ipv4(name_or_address)) {
        return name_or_address;
    }
    if (name_or_address.empty() || name_or_address.size() >= IFNAMSIZ ||
        name_or_address.find_first_of("/ \t") != std::string::npos) {
        throw base::ConfigError("--wan-interface '" + name_or_address + "': not an interface name or IPv4 address");
    }
    const auto addresses = base::interface_addresses();
    if (!addresses) {
        throw base::ConfigError("--wan-interface '" + name_or_address + "': cannot list network interfaces");
    }
    for (const base::InterfaceAddress& each : *addresses) {
        if (each.interface == name_or_address) {
            return each.address;
        }
    }
    return ADDRESS_TO_COME;
}

std::string resolve_interface_name(const std::string& name_or_address) {
    if (!is_ipv4(name_or_address)) {
        return name_or_address;
    }
    const IfaddrsPtr list = list_interfaces(name_or_address);
    for (const ifaddrs* it = list.get(); it != nullptr; it = it->ifa_next) {
        if (has_ipv4(it) && ipv4_text(it->ifa_addr) == name_or_address) {
            return it->ifa_name;
        }
    }
    throw base::ConfigError("--wan-interface '" + name_or_address + "': no interface has this address");
}

}  // namespace tgw::base
