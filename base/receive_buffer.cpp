#include "base/receive_buffer.hpp"

#include <fstream>

namespace tgw::base {

namespace {

constexpr const char* RMEM_MAX_PATH = "/proc/sys/net/core/rmem_max";

}  // namespace

std::optional<std::uint64_t> kernel_receive_buffer_cap() {
    std::ifstream file(RMEM_MAX_PATH);
    std::uint64_t bytes = 0;
    if (file >> bytes)
        return bytes;
    return std::nullopt;
}

void warn_if_receive_buffer_capped(std::ostream& out, std::string_view program, std::string_view flag,
                                   std::uint32_t requested_bytes) {
    const std::optional<std::uint64_t> cap = kernel_receive_buffer_cap();
    if (!cap || *cap >= requested_bytes)
        return;
    out << program << ": " << RMEM_MAX_PATH << " is " << *cap << " bytes, so the sockets get that, not " << flag << " "
        << requested_bytes << "; raise it (sysctl -w net.core.rmem_max=" << requested_bytes
        << ") for room for bursts\n";
}

}  // namespace tgw::base
