#include "base/interface_addresses.hpp"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cctype>
#include <memory>

namespace tgw::base {

namespace {

std::optional<in_addr> parse_ipv4(const std::string& text) {
    in_addr addr{};
    if (inet_pton(AF_INET, text.c_str(), &addr) != 1)
        return std::nullopt;
    return addr;
}

std::string dotted(in_addr addr) {
    char text[INET_ADDRSTRLEN] = {};
    inet_ntop(AF_INET, &addr, text, sizeof(text));
    return text;
}

}  // namespace

bool is_ipv4(const std::string& text) {
    return parse_ipv4(text).has_value();
}

bool is_loopback_ipv4(const std::string& text) {
    const auto addr = parse_ipv4(text);
    return addr && (ntohl(addr->s_addr) >> 24) == 127;
}

std::optional<std::vector<InterfaceAddress>> interface_addresses() {
    ifaddrs* list = nullptr;
    if (getifaddrs(&list) != 0)
        return std::nullopt;
    std::unique_ptr<ifaddrs, void (*)(ifaddrs*)> guard(list, freeifaddrs);
    std::vector<InterfaceAddress> found;
    for (const ifaddrs* it = list; it != nullptr; it = it->ifa_next) {
        if (it->ifa_addr != nullptr && it->ifa_addr->sa_family == AF_INET)
            found.push_back({it->ifa_name, dotted(reinterpret_cast<const sockaddr_in*>(it->ifa_addr)->sin_addr)});
    }
    return found;
}

std::optional<std::string> lookup_ipv4(const std::string& host) {
    if (is_ipv4(host))
        return host;
    addrinfo hints{};
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_DGRAM;
    addrinfo* found = nullptr;
    if (getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || found == nullptr)
        return std::nullopt;
    std::unique_ptr<addrinfo, void (*)(addrinfo*)> guard(found, freeaddrinfo);
    return dotted(reinterpret_cast<const sockaddr_in*>(found->ai_addr)->sin_addr);
}

bool is_host_name(const std::string& text) {
    if (text.empty() || text.size() > 253 || text.front() == '-' || text.front() == '.' || text.back() == '-')
        return false;
    for (const char c : text) {
        if (std::isalnum(static_cast<unsigned char>(c)) == 0 && c != '-' && c != '.')
            return false;
    }
    return true;
}

std::optional<std::string> route_source_address(const std::string& peer) {
    const auto addr = parse_ipv4(peer);
    if (!addr)
        return std::nullopt;
    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0)
        return std::nullopt;
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_addr = *addr;
    to.sin_port = htons(9);  // any port: connecting a UDP socket only chooses the route
    sockaddr_in from{};
    socklen_t from_size = sizeof(from);
    const bool routed = connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof(to)) == 0 &&
                        getsockname(fd, reinterpret_cast<sockaddr*>(&from), &from_size) == 0;
    close(fd);
    if (!routed)
        return std::nullopt;
    return dotted(from.sin_addr);
}

}  // namespace tgw::base
