#include "base/quiet_discovery_ports.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <utility>

#include "base/rtps_ports.hpp"

namespace tgw::base {

QuietDiscoveryPorts::QuietDiscoveryPorts(const std::string& ipv4, int domain, int participants) {
    in_addr address{};
    if (inet_pton(AF_INET, ipv4.c_str(), &address) != 1) {
        return;
    }
    for (int id = 0; id < participants; ++id) {
        const int port = metatraffic_unicast_port_wide(domain, id);
        if (port > 65535) {
            break;
        }
        const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        if (fd < 0) {
            return;
        }
        // The kernel's least buffer: what arrives is never read.
        const int smallest = 1;
        setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &smallest, sizeof(smallest));
        sockaddr_in local{};
        local.sin_family = AF_INET;
        local.sin_addr = address;
        local.sin_port = htons(static_cast<std::uint16_t>(port));
        if (bind(fd, reinterpret_cast<const sockaddr*>(&local), sizeof(local)) != 0) {
            close(fd);  // a participant's, this program's own or another's
            continue;
        }
        sockets_.push_back(fd);
        ports_.push_back(static_cast<std::uint16_t>(port));
    }
}

QuietDiscoveryPorts::~QuietDiscoveryPorts() {
    close_all();
}

QuietDiscoveryPorts::QuietDiscoveryPorts(QuietDiscoveryPorts&& other) noexcept
    : sockets_(std::move(other.sockets_)), ports_(std::move(other.ports_)) {
    other.sockets_.clear();
    other.ports_.clear();
}

QuietDiscoveryPorts& QuietDiscoveryPorts::operator=(QuietDiscoveryPorts&& other) noexcept {
    if (this != &other) {
        close_all();
        sockets_ = std::move(other.sockets_);
        ports_ = std::move(other.ports_);
        other.sockets_.clear();
        other.ports_.clear();
    }
    return *this;
}

bool QuietDiscoveryPorts::worth_it(const std::string& ipv4) {
    in_addr address{};
    if (inet_pton(AF_INET, ipv4.c_str(), &address) != 1) {
        return false;
    }
    return (ntohl(address.s_addr) >> 24) != 127;
}

void QuietDiscoveryPorts::close_all() {
    for (const int fd : sockets_) {
        close(fd);
    }
    sockets_.clear();
    ports_.clear();
}

}  // namespace tgw::base
