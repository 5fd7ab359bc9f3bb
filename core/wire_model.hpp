#pragma once

#include <cstddef>
#include <cstdint>

namespace tgw::core {

/// What a sample costs on the link beyond its serialized payload, as tbf counts it (whole Ethernet frames).
/// Defaults measured with tcpdump on the testbed's veth for the gateway's best-effort WAN writers (Debian's
/// Fast DDS 2.9): every datagram carries Ethernet 14, IPv4 20, UDP 8, the RTPS header 20, INFO_DST 16 and the
/// 60-byte statistics submessage that this Fast DDS build adds to every message: 138 bytes. Each sample adds
/// INFO_TS 12 and the DATA header 24, and its payload padded to 4. The WAN transport keeps every datagram
/// within one frame (MAX_DATAGRAM_PAYLOAD_BYTES), so a larger sample goes as DATA_FRAG submessages, one per
/// datagram, each paying the datagram's overhead, INFO_TS and a 36-byte DATA_FRAG header. Checked against
/// captures of the paper's four types (238, 262, 462, 1210 bytes) and of 3,000- and 6,000-byte samples.
/// A link fast enough not to care may allow larger datagrams (for_max_datagram); the kernel then splits
/// each into IP fragments, one Ethernet frame each.
struct WireModel {
    /// The UDP payload that fits an Ethernet frame of 1500 bytes of IP.
    static constexpr std::size_t MAX_DATAGRAM_PAYLOAD_BYTES = 1472;
    /// The largest UDP payload Fast DDS sends (its default maxMessageSize).
    static constexpr std::size_t MAX_UDP_PAYLOAD_BYTES = 65500;
    /// Ethernet 14, IPv4 20 and UDP 8 around a datagram's UDP payload (one frame's worth).
    static constexpr std::size_t FRAME_HEADER_BYTES = 42;
    /// The smallest datagram limit allowed: room for the headers and a useful fragment.
    static constexpr std::size_t MIN_DATAGRAM_PAYLOAD_BYTES = 512;

    /// The model for a WAN transport whose datagrams carry up to `max_datagram_bytes` of UDP payload, in
    /// [MIN_DATAGRAM_PAYLOAD_BYTES, MAX_UDP_PAYLOAD_BYTES]: Fast DDS's fragment and whole-sample limits move
    /// with it by the same headers as at 1472 bytes (derived, captured only at 1472).
    static WireModel for_max_datagram(std::size_t max_datagram_bytes);

    /// The statistics submessage this Fast DDS build ends every RTPS message with (header, 56 bytes of body).
    static constexpr std::size_t STATISTICS_SUBMESSAGE_BYTES = 60;
    /// The same model for a transport that leaves the statistics submessage out (WanConfig::strip_statistics).
    WireModel without_statistics() const {
        WireModel model = *this;
        model.per_datagram_bytes -= STATISTICS_SUBMESSAGE_BYTES;
        return model;
    }

    /// The INFO_DST that names the one participant a message goes to.
    static constexpr std::size_t DESTINATION_SUBMESSAGE_BYTES = 16;
    /// The same model for a transport that leaves that INFO_DST out (WanConfig::strip_destination).
    WireModel without_destination() const {
        WireModel model = *this;
        model.per_datagram_bytes -= DESTINATION_SUBMESSAGE_BYTES;
        return model;
    }

    /// The INFO_TS that stamps each sample with its source time.
    static constexpr std::size_t TIMESTAMP_SUBMESSAGE_BYTES = 12;
    /// The same model for samples that leave without it (WanConfig::strip_timestamp: compact mode's bundles).
    WireModel without_timestamp() const {
        WireModel model = *this;
        model.per_sample_bytes -= TIMESTAMP_SUBMESSAGE_BYTES;
        return model;
    }

    /// DDS Security as scripts/make-certs' governance sets it (RTPS messages signed, submessages and payloads
    /// encrypted with AES-GCM), from a loopback capture of the paper's four types at an 8,192-byte datagram limit
    /// (frames of 466, 490, 690 and 1,438 bytes against 238, 262, 462 and 1,210 plain): each message gains
    /// SRTPS_PREFIX, the INFO_SRC Fast DDS signs with it and SRTPS_POSTFIX; each of a sample's INFO_TS and DATA
    /// (or DATA_FRAG) its SEC_PREFIX, SEC_BODY header and SEC_POSTFIX; its payload AES-GCM's header, length and tag.
    static constexpr std::size_t SECURE_MESSAGE_BYTES = 72;
    static constexpr std::size_t SECURE_SUBMESSAGE_BYTES = 56;
    static constexpr std::size_t SECURE_PAYLOAD_BYTES = 44;
    /// The same model with DDS Security on the WAN participant. Where Fast DDS then starts fragmenting moves down
    /// by the same bytes (derived, not captured).
    WireModel with_security() const;

    /// The WAN transport's datagram limit (its maxMessageSize).
    std::size_t max_datagram_bytes = MAX_DATAGRAM_PAYLOAD_BYTES;

    std::size_t per_datagram_bytes = 138;
    std::size_t per_sample_bytes = 36;
    std::size_t per_fragment_bytes = 48;  ///< INFO_TS and the DATA_FRAG header
    /// Payload per DATA_FRAG: Fast DDS fills RTPS messages of 1440 bytes, 144 of them headers.
    std::size_t fragment_payload_bytes = 1296;
    /// Payloads up to this size go in one DATA submessage (1440 bytes of RTPS message less 132 of headers).
    std::size_t max_unfragmented_bytes = 1308;
    /// What protection adds to each serialized payload before it is fragmented (SECURE_PAYLOAD_BYTES), or 0.
    std::size_t payload_overhead_bytes = 0;
    /// How far below the fragmentation limit samples the gateway sizes itself (compact mode's bundles) stay. Fast
    /// DDS 2.9 fills a message up to its limit without room for the message's protection (its own "TODO Control
    /// message size if it will be encrypted" in RTPSMessageGroup::send), then adds the statistics submessage, and
    /// aborts on an assertion when the two no longer fit: a secured gateway in compact mode did, once in about six
    /// runs, with bundles 4 bytes short of it. 0 without security.
    std::size_t protected_fill_margin_bytes = 0;
    /// The margin with security: a protected HEARTBEAT (88), the message's protection (72), the statistics
    /// submessage (60), and slack for alignment.
    static constexpr std::size_t SECURE_FILL_MARGIN_BYTES = 256;

    // A reliable writer's HEARTBEATs (32 bytes, 88 protected, piggy-backed on a sample's message or alone in their own)
    // are not modelled: the WAN transport measures and charges them as they leave (CoalescingTransport).

    /// Bytes on the wire for one sample of `serialized_bytes` serialized bytes sent alone.
    std::size_t wire_bytes(std::size_t serialized_bytes) const;

    std::uint64_t wire_bits(std::size_t payload_bytes) const { return 8u * wire_bytes(payload_bytes); }

    /// Bytes on the wire of the first datagram of such a sample: its first fragment's, or the whole sample's when
    /// it does not fragment.
    std::size_t first_datagram_wire_bytes(std::size_t serialized_bytes) const;

  private:
    /// One datagram with `submessage_bytes` after the per-datagram headers: whole frames, IP fragments included.
    std::size_t datagram_wire_bytes(std::size_t submessage_bytes) const;
};

}  // namespace tgw::core
