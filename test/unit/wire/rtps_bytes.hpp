// RTPS messages and submessages as bytes, shaped as Fast DDS 2.9 writes them, for tests of what shares a datagram.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace tgw::test::rtps {

using Bytes = std::vector<std::uint8_t>;

/// A submessage: id, flags, octetsToNextHeader in the endianness the flags' E bit gives, and `body`.
inline Bytes submessage(std::uint8_t id, std::uint8_t flags, const Bytes& body) {
    const auto length = static_cast<std::uint16_t>(body.size());
    Bytes out{id, flags};
    if ((flags & 0x01) != 0) {
        out.push_back(static_cast<std::uint8_t>(length & 0xff));
        out.push_back(static_cast<std::uint8_t>(length >> 8));
    } else {
        out.push_back(static_cast<std::uint8_t>(length >> 8));
        out.push_back(static_cast<std::uint8_t>(length & 0xff));
    }
    out.insert(out.end(), body.begin(), body.end());
    return out;
}

/// INFO_TS with a timestamp whose bytes are all `stamp`.
inline Bytes info_ts(std::uint8_t stamp) {
    return submessage(0x09, 0x01, Bytes(8, stamp));
}

/// INFO_DST to the participant whose GUID prefix bytes are all `prefix` (0: GUIDPREFIX_UNKNOWN).
inline Bytes info_dst(std::uint8_t prefix) {
    return submessage(0x0e, 0x01, Bytes(12, prefix));
}

inline Bytes info_src() {
    return submessage(0x0c, 0x01, Bytes(20, 0x07));
}

/// A DATA submessage with `body_bytes` of body (a multiple of 4, as Fast DDS pads it).
inline Bytes data(std::size_t body_bytes) {
    return submessage(0x15, 0x05, Bytes(body_bytes, 0x5a));
}

/// Little-endian bytes of `value`, `bytes` of them.
inline void put_le(Bytes& out, std::uint64_t value, std::size_t bytes) {
    for (std::size_t i = 0; i < bytes; ++i) {
        out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
    }
}

/// The fields a DATA and a DATA_FRAG start with (little endian): extraFlags, octetsToInlineQos (`inline_qos_at`),
/// readerId 0, writerId `writer`, writerSN `sequence`.
inline Bytes sample_fields(const std::array<std::uint8_t, 4>& writer, std::int64_t sequence,
                           std::uint16_t inline_qos_at) {
    Bytes body{0, 0};
    put_le(body, inline_qos_at, 2);
    body.insert(body.end(), 4, 0);
    body.insert(body.end(), writer.begin(), writer.end());
    put_le(body, static_cast<std::uint64_t>(sequence) >> 32, 4);
    put_le(body, static_cast<std::uint64_t>(sequence) & 0xffffffffu, 4);
    return body;
}

/// A DATA of sample `sequence` of the writer `writer`, with 8 bytes of payload.
inline Bytes data_of(const std::array<std::uint8_t, 4>& writer, std::int64_t sequence) {
    Bytes body = sample_fields(writer, sequence, 16);
    body.insert(body.end(), 8, 0x55);
    return submessage(0x15, 0x05, body);
}

/// A DATA_FRAG of sample `sequence` of `writer`: `count` fragments of `fragment_size` from fragment `first` (from 1)
/// of a sample of `sample_size` bytes, with 8 bytes of payload (the test does not read them).
inline Bytes data_frag(const std::array<std::uint8_t, 4>& writer, std::int64_t sequence, std::uint32_t first,
                       std::uint16_t count = 1, std::uint16_t fragment_size = 1024, std::uint32_t sample_size = 6000) {
    Bytes body = sample_fields(writer, sequence, 28);
    put_le(body, first, 4);
    put_le(body, count, 2);
    put_le(body, fragment_size, 2);
    put_le(body, sample_size, 4);
    body.insert(body.end(), 8, 0x66);
    return submessage(0x16, 0x01, body);
}

/// A GAP of sample `sequence` of `writer` alone, to reader 0 (ENTITYID_UNKNOWN): gapStart `sequence`, gapList
/// from `sequence` + 1 with no bits.
inline Bytes gap(const std::array<std::uint8_t, 4>& writer, std::int64_t sequence) {
    Bytes body(4, 0);
    body.insert(body.end(), writer.begin(), writer.end());
    for (std::int64_t sn : {sequence, sequence + 1}) {
        put_le(body, static_cast<std::uint64_t>(sn) >> 32, 4);
        put_le(body, static_cast<std::uint64_t>(sn) & 0xffffffffu, 4);
    }
    put_le(body, 0, 4);
    return submessage(0x08, 0x01, body);
}

/// ENTITYID_SEDP_BUILTIN_PUBLICATIONS_WRITER: its DATA announce writers (DATA(w)).
inline constexpr std::array<std::uint8_t, 4> PUBLICATIONS{0x00, 0x00, 0x03, 0xc2};

/// A parameter: id, length (padded to 4), value, in the given endianness.
inline void put_parameter(Bytes& out, std::uint16_t pid, const Bytes& value, bool little_endian) {
    Bytes padded = value;
    padded.resize((value.size() + 3) / 4 * 4, 0);
    const auto put16 = [&](std::uint16_t v) {
        out.push_back(static_cast<std::uint8_t>(little_endian ? v & 0xff : v >> 8));
        out.push_back(static_cast<std::uint8_t>(little_endian ? v >> 8 : v & 0xff));
    };
    put16(pid);
    put16(static_cast<std::uint16_t>(padded.size()));
    out.insert(out.end(), padded.begin(), padded.end());
}

/// A CDR string: its length with the NUL, then its characters and the NUL.
inline Bytes cdr_string(const std::string& s, bool little_endian) {
    const auto n = static_cast<std::uint32_t>(s.size() + 1);
    Bytes out;
    for (int i = 0; i < 4; ++i) {
        out.push_back(static_cast<std::uint8_t>(n >> (little_endian ? 8 * i : 8 * (3 - i))));
    }
    out.insert(out.end(), s.begin(), s.end());
    out.push_back(0);
    return out;
}

/// The serialized payload of a DATA(w): a participant GUID, the topic and type names, then the sentinel.
inline Bytes publication(const std::string& topic, bool little_endian) {
    Bytes payload{0x00, static_cast<std::uint8_t>(little_endian ? 0x03 : 0x02), 0, 0};
    put_parameter(payload, 0x0050, Bytes(16, 0x01), little_endian);  // PID_PARTICIPANT_GUID
    put_parameter(payload, 0x0005, cdr_string(topic, little_endian), little_endian);
    put_parameter(payload, 0x0007, cdr_string("PaperMessage", little_endian), little_endian);  // PID_TYPE_NAME
    put_parameter(payload, 0x0001, {}, little_endian);
    return payload;
}

/// A DATA of the publications writer (little-endian submessage) with `payload`, and inline QoS when asked.
inline Bytes announcement_data(const Bytes& payload, std::int64_t sequence = 7, bool inline_qos = false) {
    Bytes body = sample_fields(PUBLICATIONS, sequence, 16);
    if (inline_qos) {
        put_parameter(body, 0x0070, Bytes(16, 0x02), true);  // PID_KEY_HASH
        put_parameter(body, 0x0001, {}, true);
    }
    body.insert(body.end(), payload.begin(), payload.end());
    return submessage(0x15, static_cast<std::uint8_t>(0x05 | (inline_qos ? 0x02 : 0x00)), body);
}

/// A HEARTBEAT submessage (28 bytes of body: reader and writer ids, first and last sequence numbers, count)
/// from the writer whose entity id bytes are all `writer`, announcing 1 .. `last`.
inline Bytes heartbeat(std::uint8_t writer = 0x11, std::uint8_t last = 1, std::uint8_t count = 1) {
    Bytes body(28, 0);
    std::fill(body.begin() + 4, body.begin() + 8, writer);
    body[12] = 1;     // first sequence number, low word (little endian)
    body[20] = last;  // last sequence number, low word
    body[24] = count;
    return submessage(0x07, 0x01, body);
}

/// An ACKNACK submessage from the reader whose entity id bytes are all `reader` to the writer whose entity id
/// bytes are all `writer`: a sequence number set based at `base` with `bits` bits (all clear), then the count.
inline Bytes acknack(std::uint8_t reader = 0x22, std::uint8_t writer = 0x11, std::uint8_t base = 0,
                     std::uint8_t bits = 0, std::uint8_t count = 1) {
    Bytes body(4 + 4 + 8 + 4 + 4 * ((bits + 31u) / 32u) + 4, 0);
    std::fill(body.begin(), body.begin() + 4, reader);
    std::fill(body.begin() + 4, body.begin() + 8, writer);
    body[12] = base;  // the set's base, low word (little endian)
    body[16] = bits;
    body[body.size() - 4] = count;
    return submessage(0x06, 0x01, body);
}

/// Fast DDS's network-statistics submessage (id 0x80, big-endian, 56 bytes), which its transport fills in.
inline Bytes statistics(std::uint8_t fill) {
    return submessage(0x80, 0x00, Bytes(56, fill));
}

/// Fills in the statistics submessage `message` ends with as Fast DDS's UDP transport does when it sends it
/// (little-endian, whatever the flags say): the destination 10.77.0.6:`port`, `seconds` and a half, and the
/// sender's `sequence`-th datagram to that destination.
inline void stamp(Bytes& message, std::uint32_t seconds, std::uint64_t sequence, std::uint32_t port = 7411) {
    const std::size_t body = message.size() - 56;
    const auto put = [&](std::size_t at, std::uint64_t value, std::size_t bytes) {
        for (std::size_t i = 0; i < bytes; ++i) {
            message[body + at + i] = static_cast<std::uint8_t>(value >> (8 * i));
        }
    };
    put(0, 1, 4);  // LOCATOR_KIND_UDPv4
    put(4, port, 4);
    put(16, 0, 4);
    message[body + 20] = 10;
    message[body + 21] = 77;
    message[body + 22] = 0;
    message[body + 23] = 6;
    put(24, seconds, 4);
    put(28, 0x80000000u, 4);
    put(32, sequence, 8);
}

/// An RTPS message's protection as a whole (DDS Security, rtps_protection_kind SIGN): SRTPS_PREFIX (transformation
/// id, session id, IV suffix: 20 bytes), `inner` as they are, SRTPS_POSTFIX (common MAC 16 bytes, no receiver MACs).
inline std::vector<Bytes> signed_rtps(std::initializer_list<Bytes> inner) {
    std::vector<Bytes> out{submessage(0x33, 0x01, Bytes(20, 0x3c))};
    out.insert(out.end(), inner.begin(), inner.end());
    out.push_back(submessage(0x34, 0x01, Bytes(20, 0x4d)));
    return out;
}

/// A message of the eProsima participant whose GUID prefix bytes are all `participant`.
inline Bytes message(std::initializer_list<Bytes> submessages, std::uint8_t participant = 0x01) {
    Bytes out{'R', 'T', 'P', 'S', 2, 3, 0x01, 0x0f};
    out.insert(out.end(), 12, participant);
    for (const Bytes& s : submessages) {
        out.insert(out.end(), s.begin(), s.end());
    }
    return out;
}

/// A message of the eProsima participant `participant` whose submessages are `submessages`, in order.
inline Bytes message(const std::vector<Bytes>& submessages, std::uint8_t participant = 0x01) {
    Bytes out{'R', 'T', 'P', 'S', 2, 3, 0x01, 0x0f};
    out.insert(out.end(), 12, participant);
    for (const Bytes& s : submessages) {
        out.insert(out.end(), s.begin(), s.end());
    }
    return out;
}

}  // namespace tgw::test::rtps
