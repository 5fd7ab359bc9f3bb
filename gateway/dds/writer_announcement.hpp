// Which topic a WAN writer's announcement (SEDP DATA(w)) is of. Pure bytes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "gateway/dds/rtps_sample_refs.hpp"

namespace tgw::dds {

/// ENTITYID_SEDP_BUILTIN_PUBLICATIONS_WRITER (DDSI-RTPS 9.3.1.5): its DATA announce the participant's writers.
inline constexpr std::uint8_t SEDP_PUBLICATIONS_WRITER_ID[4] = {0x00, 0x00, 0x03, 0xc2};

/// The writers' announcements found in an RTPS message: the topics they name (views into the message) and which
/// of the publications writer's samples the first is.
struct WriterAnnouncements {
    static constexpr std::size_t MAX_TOPICS = 8;
    std::array<std::string_view, MAX_TOPICS> topics{};
    std::size_t count = 0;
    RtpsSampleRef first;
};

/// The writers' announcements `message` carries: DATA of the SEDP publications writer (at most MAX_TOPICS), each
/// with a parameter list (PL_CDR, either endianness) that names its topic (PID_TOPIC_NAME), beside nothing but
/// INFO_DST, INFO_TS, a HEARTBEAT (the publications writer's, which Fast DDS may put after them) and Fast DDS's
/// statistics. nullopt for anything else: a dispose, a fragment, another submessage beside them, or bytes that do
/// not read.
std::optional<WriterAnnouncements> writer_announcements(const std::uint8_t* message, std::size_t size);

}  // namespace tgw::dds
