// One UDP datagram built from several whole RTPS messages of one participant. Pure bytes: no Fast DDS header.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace tgw::wire {

/// Packs RTPS messages that one participant sends to the same destinations into one datagram: the first message
/// whole, each later one without its 20-byte header, as if one writer had put all their submessages in one
/// message. A receiver then reads every sample from one socket read.
///
/// Receivers keep per-message state across submessages (destination participant, source timestamp), so a message
/// is appended only when it reads the same alone and appended: it must set the destination again when one is in
/// force (Fast DDS 2.9 ignores an INFO_DST to GUIDPREFIX_UNKNOWN, so the destination cannot be reset; an INFO_DST
/// that names the participant already in force is left out, 16 bytes), and a
/// timestamp in force is invalidated (INFO_TS with the I flag, 4 bytes) before a message that sets none. A
/// message whose state changes are not tracked (INFO_SRC, INFO_REPLY), whose last submessage runs to the end,
/// or that does not end on a 4-byte boundary closes the datagram. A message protected as a whole (DDS Security's
/// SRTPS_PREFIX) goes alone: its signature covers its own submessages, and a receiver reads nothing after them.
///
/// Fast DDS built with statistics (as Debian's is) ends every message with its network-statistics submessage,
/// which its sending transport fills in and its receiver expects last, once. Only the last message's is kept.
class RtpsDatagram {
  public:
    static constexpr std::size_t HEADER_BYTES = 20;

    explicit RtpsDatagram(std::size_t max_bytes);

    /// Appends `message` if it can share the datagram and fits in max_bytes; false leaves the datagram as it was.
    /// An empty datagram takes any message of at most max_bytes, well-formed or not (then it is closed).
    bool append(const std::uint8_t* message, std::size_t size);

    void clear();
    bool empty() const { return messages_ == 0; }
    const std::uint8_t* data() const { return bytes_.data(); }
    std::size_t size() const { return bytes_.size(); }
    /// How many messages were appended since the last clear().
    std::size_t messages() const { return messages_; }

    /// The bytes of HEARTBEAT submessages (headers included) in one RTPS message: what a reliable writer adds
    /// to a sample's message beyond the wire model. 0 for a message that is not well formed. In a message
    /// protected as a whole, whose submessages are encrypted one by one, a HEARTBEAT cannot be told from the rest:
    /// every protected submessage after the first two (the sample's INFO_TS and DATA, or DATA_FRAG) counts as one.
    static std::size_t heartbeat_bytes(const std::uint8_t* message, std::size_t size);
    /// The bytes of the statistics submessage (header included) that ends a well-formed eProsima RTPS message,
    /// or 0 when it does not end with one. Receivers read it only for eProsima's statistics module.
    static std::size_t statistics_trailer_bytes(const std::uint8_t* message, std::size_t size);
    /// True for a well-formed, unprotected message whose only submessages (besides INFO_DST, INFO_TS, PAD and the
    /// statistics trailer) are HEARTBEATs and GAPs of applications' writers: a reliable writer's control alone,
    /// which may wait a moment to ride in the datagram of the next message to the same destination.
    static bool user_control_only(const std::uint8_t* message, std::size_t size);
    /// The sending participant's GUID prefix, from the message's header; nullopt for bytes that are not RTPS.
    static std::optional<std::array<std::uint8_t, 12>> sender(const std::uint8_t* message, std::size_t size);
    /// The bytes of the INFO_DST (header included) that a well-formed, unprotected message starts with when it is
    /// the message's only one and names a participant; else 0. Sent only to that participant's unicast
    /// locators, the message reads the same without it: a receiver takes a message that names nobody as its own.
    static std::size_t leading_destination_bytes(const std::uint8_t* message, std::size_t size);
    /// What a transport may leave out of one message, from one reading of it: its leading INFO_DST
    /// (leading_destination_bytes), its statistics trailer (statistics_trailer_bytes), and the INFO_TS of a
    /// message that carries one sample: an unprotected [INFO_DST] INFO_TS DATA [statistics], whose INFO_TS comes
    /// right after the header or the INFO_DST (the sample then has no source timestamp; the caller knows whether
    /// its payload holds one).
    struct Strippable {
        std::size_t destination_bytes = 0;
        std::size_t trailer_bytes = 0;
        std::size_t timestamp_bytes = 0;
        /// It holds a DATA or DATA_FRAG of an application's writer, or protected submessages that may be one.
        bool carries_user_sample = false;
    };
    static Strippable strippable(const std::uint8_t* message, std::size_t size);
    /// The bytes of PAD submessages to append to a datagram that does not end with a statistics submessage (its
    /// own was left out) so that Fast DDS's UDP transport does not take it for one: the transport fills in the
    /// last STATISTICS_BYTES of every datagram whose byte there is the submessage's id, over whatever they hold
    /// (a payload's bytes, a protected message's signature). 0 for most datagrams; else a multiple of 4.
    static std::size_t padding_against_statistics_fill(const std::uint8_t* datagram, std::size_t size);
    static constexpr std::size_t STATISTICS_BYTES = 60;
    static constexpr std::uint8_t PAD_SUBMESSAGE[4] = {0x01, 0x01, 0x00, 0x00};

  private:
    /// What a receiver's state is after a run of submessages, and whether more may follow.
    struct Shape {
        bool well_formed = false;
        bool mergeable = false;              ///< nothing untracked, no run-to-end submessage, 4-byte aligned
        bool rtps_protected = false;         ///< DDS Security protects it as a whole (SRTPS_PREFIX)
        bool sets_destination = false;       ///< the first submessage is an INFO_DST to a participant
        std::size_t destinations = 0;        ///< INFO_DST submessages
        bool protected_submessages = false;  ///< DDS Security protects some of its submessages (SEC_PREFIX)
        bool sets_timestamp_first = false;   ///< an INFO_TS comes before the first submessage that is not INFO_*
        bool destination_in_force = false;   ///< at the end
        std::size_t destination_at = 0;      ///< where the GUID prefix of the last INFO_DST to a participant is
        bool timestamp_in_force = false;     ///< at the end
        std::size_t trailer_bytes = 0;       ///< the statistics submessage it ends with, header included
        bool trailer_last = false;           ///< the statistics submessage is the last submessage
        std::size_t heartbeat_bytes = 0;     ///< HEARTBEAT submessages, headers included
        bool carries_user_sample = false;    ///< as in Strippable
        bool user_control_only = false;      ///< as in user_control_only(), but for protection
        /// [INFO_DST] INFO_TS DATA [statistics] and nothing else: the INFO_TS's bytes (header included), else 0.
        std::size_t lone_sample_timestamp_bytes = 0;
    };
    static Shape shape_of(const std::uint8_t* message, std::size_t size);
    void note_destination(const std::uint8_t* message, const Shape& shape);

    std::size_t max_bytes_;
    std::vector<std::uint8_t> bytes_;
    std::size_t messages_ = 0;
    bool closed_ = false;
    bool destination_in_force_ = false;
    std::array<std::uint8_t, 12> destination_{};  ///< the participant in force, while destination_in_force_
    bool timestamp_in_force_ = false;
    std::size_t trailer_bytes_ = 0;
};

}  // namespace tgw::wire
