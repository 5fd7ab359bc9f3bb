#include "wire/send_stamp.hpp"

#include <algorithm>
#include <cstring>

#include "base/byte_order.hpp"
#include "wire/rtps_datagram.hpp"

namespace tgw::wire {

namespace {

// The submessage's body after its 4-byte header: the destination locator (kind 4, port 4, address 16), the
// timestamp (seconds 4, fraction of 2^-32 s 4), then the sequence (count 8, bytes 8, high bytes 2) and padding.
constexpr std::size_t BODY_BYTES = 56;
constexpr std::size_t SECONDS_AT = 24;
constexpr std::size_t FRACTION_AT = 28;
constexpr std::size_t SEQUENCE_AT = 32;

}  // namespace

std::optional<SendStamp> read_send_stamp(const std::uint8_t* datagram, std::size_t size) {
    const std::optional<std::array<std::uint8_t, 12>> sender = RtpsDatagram::sender(datagram, size);
    if (!sender || RtpsDatagram::statistics_trailer_bytes(datagram, size) != RtpsDatagram::STATISTICS_BYTES)
        return std::nullopt;
    const std::uint8_t* body = datagram + size - BODY_BYTES;
    SendStamp stamp;
    stamp.sender = *sender;
    std::copy(body, body + stamp.destination.size(), stamp.destination.begin());
    const auto seconds = static_cast<std::int32_t>(base::load_little_endian<std::uint32_t>(body + SECONDS_AT));
    const std::uint32_t fraction = base::load_little_endian<std::uint32_t>(body + FRACTION_AT);
    if (seconds <= 0)
        return std::nullopt;  // never filled in: the sender's transport did not stamp it
    const auto ns = static_cast<std::int64_t>(seconds) * 1'000'000'000 +
                    static_cast<std::int64_t>((static_cast<std::uint64_t>(fraction) * 1'000'000'000) >> 32);
    stamp.sent = base::wall_from_ns(ns);
    stamp.sequence = base::load_little_endian<std::uint64_t>(body + SEQUENCE_AT);
    return stamp;
}

}  // namespace tgw::wire
