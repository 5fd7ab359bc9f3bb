// Keeps a host's kernel from answering discovery sent to participants that are not there.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tgw::base {

/// A base camp that knows the robot by its address alone announces itself to the discovery ports of several
/// participant indices there (Cyclone DDS: indices 0 to 9, every SPDP period), and the robot's kernel answers each
/// port no one has bound with an ICMP port unreachable of about 400 bytes, over the radio, outside any schedule:
/// about 80 in a 70 s run on the testbed, bursts of six that took a 4,000 bit/s link for 4 s each.
///
/// This binds, on one local IPv4 address, the metatraffic unicast ports of participants 0 .. participants-1 of a
/// domain that are still free (the caller's own participant has taken its port before), and never reads them: a
/// datagram to a bound port is dropped without an answer once the small buffer is full. A participant started
/// later on the same address finds those ports taken and, as Fast DDS does, takes the next free index (peers still
/// learn its ports from its announcements); so use it only where the address is the radio's and the domain this
/// program's own, never on loopback, where every program of the host shares the ports.
class QuietDiscoveryPorts {
  public:
    /// Cyclone DDS's MaxAutoParticipantIndex default (9): the indices a Cyclone peer announces itself to.
    static constexpr int CYCLONE_PARTICIPANT_INDICES = 10;

    QuietDiscoveryPorts() = default;
    /// Binds what it can; a port another socket holds is left to it. Never throws: a port it cannot bind only
    /// means its ICMP is still sent.
    QuietDiscoveryPorts(const std::string& ipv4, int domain, int participants = CYCLONE_PARTICIPANT_INDICES);
    ~QuietDiscoveryPorts();
    QuietDiscoveryPorts(QuietDiscoveryPorts&& other) noexcept;
    QuietDiscoveryPorts& operator=(QuietDiscoveryPorts&& other) noexcept;
    QuietDiscoveryPorts(const QuietDiscoveryPorts&) = delete;
    QuietDiscoveryPorts& operator=(const QuietDiscoveryPorts&) = delete;

    /// The ports it holds.
    const std::vector<std::uint16_t>& ports() const { return ports_; }

    /// Whether `ipv4` is one the ports should be held on: a valid address not in 127.0.0.0/8.
    static bool worth_it(const std::string& ipv4);

  private:
    void close_all();

    std::vector<int> sockets_;
    std::vector<std::uint16_t> ports_;
};

}  // namespace tgw::base
