// This host's IPv4 interfaces as the kernel lists them now (of this network namespace): what a participant may
// be bound to, and which of them carries the traffic to a given peer.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace tgw::base {

struct InterfaceAddress {
    std::string interface;  ///< its name, "lo", "wlan0"
    std::string address;    ///< dotted IPv4
};

/// Every IPv4 address of this host's interfaces, loopback included, in the kernel's order; nullopt when the
/// kernel will not list them.
std::optional<std::vector<InterfaceAddress>> interface_addresses();

/// The address this host would send from to reach the IPv4 `peer`, by its routing table (a UDP socket is
/// connected, nothing is sent); nullopt when `peer` is not an IPv4 address or no route leads there.
std::optional<std::string> route_source_address(const std::string& peer);

/// The first IPv4 address the resolver (/etc/hosts, DNS, mDNS as nsswitch.conf says) has for `host` now; nullopt
/// when it has none. An IPv4 address is its own. May block for as long as the resolver takes.
std::optional<std::string> lookup_ipv4(const std::string& host);

/// Whether `text` could be a host name (RFC 1123: letters, digits, '-' and '.', up to 253 characters).
bool is_host_name(const std::string& text);

/// Whether `text` is a dotted IPv4 address.
bool is_ipv4(const std::string& text);

/// Whether `text` is an IPv4 address in 127.0.0.0/8.
bool is_loopback_ipv4(const std::string& text);

}  // namespace tgw::base
