// Which topic a WAN writer's announcement (SEDP DATA(w)) is of. Pure bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "gateway/dds/rtps_sample_refs.hpp"

namespace tgw::dds {

/// ENTITYID_SEDP_BUILTIN_PUBLICATIONS_WRITER (DDSI-RTPS 9.3.1.5): its DATA announce the participant's writers.
inline constexpr std::uint8_t SEDP_PUBLICATIONS_WRITER_ID[4] = {0x00, 0x00, 0x03, 0xc2};

/// A writer's announcement found in an RTPS message: the topic it names (a view into the message) and which of
/// the publications writer's samples it is.
struct WriterAnnouncement {
    std::string_view topic;
    RtpsSampleRef ref;
};

/// The writer's announcement `message` carries: one DATA of the SEDP publications writer, alone but for INFO_DST,
/// INFO_TS and Fast DDS's statistics, whose parameter list (PL_CDR, either endianness) names the topic
/// (PID_TOPIC_NAME). nullopt for anything else: a dispose, a fragment, another submessage beside it, or bytes
/// that do not read.
std::optional<WriterAnnouncement> writer_announcement(const std::uint8_t* message, std::size_t size);

}  // namespace tgw::dds
