#include "wire/rtps_datagram.hpp"

#include <algorithm>
#include <cstring>

#include "wire/rtps_submessage.hpp"

namespace tgw::wire {

namespace {

using namespace rtps_bytes;

constexpr std::uint8_t VENDOR_EPROSIMA[2] = {0x01, 0x0f};
constexpr std::size_t VENDOR_OFFSET = 6;
constexpr std::uint8_t FLAG_INVALIDATE = 0x02;  ///< INFO_TS: no timestamp follows

constexpr bool is_info(std::uint8_t id) {
    return id == PAD || id == INFO_TS || id == INFO_SRC || id == INFO_REPLY_IP4 || id == INFO_DST || id == INFO_REPLY;
}

bool is_zero(const std::uint8_t* bytes, std::size_t size) {
    return std::all_of(bytes, bytes + size, [](std::uint8_t b) { return b == 0; });
}

}  // namespace

RtpsDatagram::RtpsDatagram(std::size_t max_bytes) : max_bytes_(max_bytes) {
    bytes_.reserve(max_bytes);
}

void RtpsDatagram::clear() {
    bytes_.clear();
    messages_ = 0;
    closed_ = false;
    destination_in_force_ = false;
    timestamp_in_force_ = false;
    trailer_bytes_ = 0;
}

RtpsDatagram::Shape RtpsDatagram::shape_of(const std::uint8_t* message, std::size_t size) {
    if (size < HEADER_BYTES || std::memcmp(message, "RTPS", 4) != 0) {
        return Shape{};
    }
    const bool eprosima = std::memcmp(message + VENDOR_OFFSET, VENDOR_EPROSIMA, 2) == 0;
    Shape shape;
    shape.mergeable = true;
    bool leading_info = true;  // still in the run of INFO_* submessages the message starts with
    std::size_t protected_groups = 0;
    std::size_t group_start = 0;  // where the SEC_PREFIX of the protected submessage being read is
    std::size_t protected_extra_bytes = 0;
    // The submessages other than a leading INFO_DST and the statistics trailer, in order, as far as they read
    // INFO_TS DATA: 0 none yet, 1 the INFO_TS, 2 the DATA after it, 3 anything else.
    int lone_sample = 0;
    std::size_t timestamp_bytes = 0;
    // HEARTBEATs and GAPs of applications' writers seen, and nothing else but INFO_* and the trailer: -1 once
    // anything else is.
    int user_controls = 0;
    std::size_t pos = HEADER_BYTES;
    while (pos < size) {
        if (size - pos < SUBMESSAGE_HEADER_BYTES) {
            return Shape{};
        }
        const std::uint8_t* sub = message + pos;
        const std::uint8_t id = sub[0];
        const std::size_t length = octets_to_next_header(sub);
        const std::size_t body = pos + SUBMESSAGE_HEADER_BYTES;
        if (body + length > size) {
            return Shape{};
        }
        if (length == 0 && id != INFO_TS && id != PAD) {
            // Runs to the end of the message: nothing can follow it.
            shape.mergeable = false;
        }
        if (id == INFO_DST) {
            if (length < GUID_PREFIX_BYTES) {
                return Shape{};
            }
            ++shape.destinations;
            // An INFO_DST to GUIDPREFIX_UNKNOWN leaves a Fast DDS receiver's destination as it was.
            if (!is_zero(message + body, GUID_PREFIX_BYTES)) {
                shape.destination_in_force = true;
                shape.destination_at = body;
                shape.sets_destination = shape.sets_destination || pos == HEADER_BYTES;
            }
        } else if (id == INFO_TS) {
            shape.timestamp_in_force = (sub[1] & FLAG_INVALIDATE) == 0;
            shape.sets_timestamp_first = shape.sets_timestamp_first || leading_info;
        } else if (id == SRTPS_PREFIX) {
            shape.rtps_protected = true;
            shape.mergeable = false;
        } else if (id == INFO_SRC || id == INFO_REPLY || id == INFO_REPLY_IP4) {
            shape.mergeable = false;
        } else if (id == HEARTBEAT) {
            shape.heartbeat_bytes += SUBMESSAGE_HEADER_BYTES + length;
        }
        const bool trailer = eprosima && id == EPROSIMA_STATISTICS;
        if (user_controls >= 0 && !is_info(id) && !trailer) {
            // Both carry the writer's id second, after the reader's (DDSI-RTPS 9.4.5.6, 9.4.5.8).
            constexpr std::size_t CONTROL_WRITER_KIND_AT = 7;
            const bool user_control =
                (id == HEARTBEAT || id == GAP) && length > CONTROL_WRITER_KIND_AT &&
                (message[body + CONTROL_WRITER_KIND_AT] & BUILTIN_ENTITY_KIND_BITS) != BUILTIN_ENTITY_KIND_BITS;
            user_controls = user_control ? user_controls + 1 : -1;
        }
        if (id == DATA || id == DATA_FRAG) {
            const bool builtin =
                length > SAMPLE_WRITER_ID_OFFSET + 3 &&
                (message[body + SAMPLE_WRITER_ID_OFFSET + 3] & BUILTIN_ENTITY_KIND_BITS) == BUILTIN_ENTITY_KIND_BITS;
            shape.carries_user_sample = shape.carries_user_sample || !builtin;
        } else if (id == SEC_PREFIX) {
            group_start = pos;
            shape.protected_submessages = true;
        }
        leading_info = leading_info && is_info(id);
        // Receivers step to the next 4-byte boundary.
        const std::size_t next = body + ((length + 3) & ~std::size_t{3});
        const bool leading_destination = id == INFO_DST && pos == HEADER_BYTES;
        if (!leading_destination && !trailer) {
            if (lone_sample == 0 && id == INFO_TS && (sub[1] & FLAG_INVALIDATE) == 0) {
                lone_sample = 1;
                timestamp_bytes = next - pos;
            } else if (lone_sample == 1 && id == DATA) {
                lone_sample = 2;
            } else {
                lone_sample = 3;
            }
        }
        if (trailer) {
            shape.trailer_last = next == size;
            if (!shape.trailer_last) {
                shape.mergeable = false;  // not where the receiver expects it
            }
            shape.trailer_bytes = SUBMESSAGE_HEADER_BYTES + length;
        }
        if (id == SEC_POSTFIX && ++protected_groups > 2) {
            protected_extra_bytes += next - group_start;
        }
        pos = next;
    }
    if (shape.rtps_protected) {
        shape.heartbeat_bytes += protected_extra_bytes;
    }
    shape.carries_user_sample = shape.carries_user_sample || shape.rtps_protected || shape.protected_submessages;
    shape.user_control_only = user_controls > 0 && !shape.rtps_protected && !shape.protected_submessages;
    if (lone_sample == 2 && !shape.rtps_protected && !shape.protected_submessages) {
        shape.lone_sample_timestamp_bytes = timestamp_bytes;
    }
    if (pos != size) {
        shape.mergeable = false;  // the last submessage is not padded to 4 bytes
    }
    shape.well_formed = true;
    return shape;
}

std::size_t RtpsDatagram::heartbeat_bytes(const std::uint8_t* message, std::size_t size) {
    return shape_of(message, size).heartbeat_bytes;
}

bool RtpsDatagram::user_control_only(const std::uint8_t* message, std::size_t size) {
    const Shape shape = shape_of(message, size);
    return shape.well_formed && shape.mergeable && shape.user_control_only;
}

std::optional<std::array<std::uint8_t, 12>> RtpsDatagram::sender(const std::uint8_t* message, std::size_t size) {
    constexpr std::size_t PREFIX_AT = 8;  // after "RTPS", the version (2) and the vendor (2)
    if (message == nullptr || size < HEADER_BYTES || std::memcmp(message, "RTPS", 4) != 0)
        return std::nullopt;
    std::array<std::uint8_t, 12> prefix{};
    std::copy(message + PREFIX_AT, message + PREFIX_AT + prefix.size(), prefix.begin());
    return prefix;
}

std::size_t RtpsDatagram::statistics_trailer_bytes(const std::uint8_t* message, std::size_t size) {
    return strippable(message, size).trailer_bytes;
}

std::size_t RtpsDatagram::leading_destination_bytes(const std::uint8_t* message, std::size_t size) {
    return strippable(message, size).destination_bytes;
}

RtpsDatagram::Strippable RtpsDatagram::strippable(const std::uint8_t* message, std::size_t size) {
    const Shape shape = shape_of(message, size);
    Strippable out;
    if (!shape.well_formed) {
        return out;
    }
    if (shape.trailer_last) {
        out.trailer_bytes = shape.trailer_bytes;
    }
    if (!shape.rtps_protected && !shape.protected_submessages && shape.sets_destination && shape.destinations == 1 &&
        octets_to_next_header(message + HEADER_BYTES) == GUID_PREFIX_BYTES) {
        out.destination_bytes = SUBMESSAGE_HEADER_BYTES + GUID_PREFIX_BYTES;
    }
    out.timestamp_bytes = shape.lone_sample_timestamp_bytes;
    out.carries_user_sample = shape.carries_user_sample;
    return out;
}

std::size_t RtpsDatagram::padding_against_statistics_fill(const std::uint8_t* datagram, std::size_t size) {
    // Most datagrams have no statistics id where the transport looks: decided without reading the submessages.
    if (size < HEADER_BYTES + STATISTICS_BYTES || datagram[size - STATISTICS_BYTES] != EPROSIMA_STATISTICS ||
        statistics_trailer_bytes(datagram, size) != 0) {
        return 0;  // or its own statistics submessage, the one to fill in
    }
    // Each PAD moves the byte the transport looks at 4 bytes on; the last bytes of the datagram, then the PADs'
    // own (id 0x01, flags 0x01, length 0), none of which is the statistics id.
    std::size_t padding = 0;
    while (size + padding >= HEADER_BYTES + STATISTICS_BYTES) {
        const std::size_t at = size + padding - STATISTICS_BYTES;
        const std::uint8_t byte = at < size ? datagram[at] : PAD_SUBMESSAGE[(at - size) % 4];
        if (byte != EPROSIMA_STATISTICS) {
            break;
        }
        padding += sizeof(PAD_SUBMESSAGE);
    }
    return padding;
}

bool RtpsDatagram::append(const std::uint8_t* message, std::size_t size) {
    const Shape shape = shape_of(message, size);
    if (empty()) {
        if (size > max_bytes_) {
            return false;
        }
        bytes_.assign(message, message + size);
        messages_ = 1;
        closed_ = !shape.well_formed || !shape.mergeable;
        note_destination(message, shape);
        timestamp_in_force_ = shape.timestamp_in_force;
        trailer_bytes_ = shape.trailer_bytes;
        return true;
    }
    if (closed_ || !shape.well_formed || shape.rtps_protected ||
        std::memcmp(message, bytes_.data(), HEADER_BYTES) != 0 || (destination_in_force_ && !shape.sets_destination)) {
        return false;
    }
    const bool invalidate_timestamp = timestamp_in_force_ && !shape.sets_timestamp_first;
    // Its leading INFO_DST names the participant in force already.
    const bool same_destination =
        destination_in_force_ && !shape.protected_submessages &&
        octets_to_next_header(message + HEADER_BYTES) == GUID_PREFIX_BYTES &&
        std::memcmp(message + HEADER_BYTES + SUBMESSAGE_HEADER_BYTES, destination_.data(), GUID_PREFIX_BYTES) == 0;
    const std::size_t from = HEADER_BYTES + (same_destination ? SUBMESSAGE_HEADER_BYTES + GUID_PREFIX_BYTES : 0);
    const std::size_t kept = bytes_.size() - trailer_bytes_;
    const std::size_t added = (invalidate_timestamp ? SUBMESSAGE_HEADER_BYTES : 0) + size - from;
    if (kept + added > max_bytes_) {
        return false;
    }
    bytes_.resize(kept);
    if (invalidate_timestamp) {
        const std::uint8_t info_ts[SUBMESSAGE_HEADER_BYTES] = {INFO_TS, FLAG_LITTLE_ENDIAN | FLAG_INVALIDATE, 0, 0};
        bytes_.insert(bytes_.end(), info_ts, info_ts + SUBMESSAGE_HEADER_BYTES);
    }
    bytes_.insert(bytes_.end(), message + from, message + size);
    ++messages_;
    // Alone, the message starts from a reset receiver; appended, from the state in force. It sets the
    // destination again whenever one is in force (checked above), and the timestamp is set or invalidated, so
    // the state after it is its own.
    closed_ = !shape.mergeable;
    note_destination(message, shape);
    timestamp_in_force_ = shape.timestamp_in_force;
    trailer_bytes_ = shape.trailer_bytes;
    return true;
}

void RtpsDatagram::note_destination(const std::uint8_t* message, const Shape& shape) {
    destination_in_force_ = shape.destination_in_force;
    if (destination_in_force_) {
        std::memcpy(destination_.data(), message + shape.destination_at, GUID_PREFIX_BYTES);
    }
}

}  // namespace tgw::wire
