// How the relay's participant on the camp's own domain is bound: off the radio unless told otherwise.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include "base/interface_addresses.hpp"
#include "base/peer_transport.hpp"

namespace tgw::basecamp {

/// The addresses the camp's domain uses when --local-interface names none: every IPv4 address of `host` but
/// those of the interface that holds `wan_address`, loopback included. Empty when `wan_address` is on no
/// interface of `host` (or is loopback): then nothing need be kept off, and Fast DDS's defaults stand.
std::vector<std::string> camp_addresses_off_the_wan(const std::vector<base::InterfaceAddress>& host,
                                                    const std::string& wan_address);

/// The local address the WAN participant of `wan` uses: its --interface, else the route to its first peer or
/// to its discovery server; nullopt when none says.
std::optional<std::string> wan_local_address(const base::PeerTransport& wan);

/// Configures `qos` for the camp's domain `domain` (base::apply_host_transport: UDP alone, so camp tools of any
/// user reach it): on the interface `local` names; otherwise on camp_addresses_off_the_wan(this host,
/// wan_local_address(wan)), so that camp tools on loopback or the camp's LAN hear the relay with no flags and no
/// camp-domain discovery crosses the radio. Returns the addresses used (empty: every interface). Throws
/// ConfigError for an interface that names no address.
std::vector<std::string> apply_camp_domain_transport(eprosima::fastdds::dds::DomainParticipantQos& qos,
                                                     const base::PeerTransport& local, const base::PeerTransport& wan,
                                                     int domain);

/// Where the camp's domain is, for the relay's first line: "the camp's domain on 127.0.0.1, 192.168.1.20 (kept
/// off the WAN's 10.77.0.2)", "... on 127.0.0.1 (--local-interface)", "... on every interface". `addresses`:
/// what apply_camp_domain_transport returned for `local` and `wan`.
std::string describe_camp_domain(const std::vector<std::string>& addresses, const base::PeerTransport& local,
                                 const base::PeerTransport& wan);

}  // namespace tgw::basecamp
