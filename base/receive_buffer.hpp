// How much a participant's UDP sockets may hold while its receive thread is busy (SO_RCVBUF), and telling the user
// when the kernel gives less. One 64 KiB sample is one datagram of 64 KiB: the system's default buffer, 208 KiB
// (net.core.rmem_default), holds three, and a reader that falls behind by a fourth loses whole samples.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string_view>

namespace tgw::base {

/// Receive buffer for the participants that take large samples off a socket: the gateway's robot side, the camp's
/// WAN side. The kernel spends it only on what waits to be read.
constexpr std::uint32_t DEFAULT_RECEIVE_BUFFER_BYTES = 4u << 20;
/// Fast DDS refuses a receive buffer smaller than its largest message (65500 B).
constexpr std::uint32_t MIN_RECEIVE_BUFFER_BYTES = 1u << 16;
constexpr std::uint32_t MAX_RECEIVE_BUFFER_BYTES = 1u << 30;

/// net.core.rmem_max, the kernel's cap on SO_RCVBUF (it caps without a word); none when it cannot be read.
std::optional<std::uint64_t> kernel_receive_buffer_cap();

/// Writes one line to `out` when the kernel will give `program`'s sockets less than `flag` asked for, with the
/// sysctl that raises the cap; nothing otherwise.
void warn_if_receive_buffer_capped(std::ostream& out, std::string_view program, std::string_view flag,
                                   std::uint32_t requested_bytes);

}  // namespace tgw::base
