// The full mission archive (tm-basecamp merge): every sample the robot produced, exactly once, with where and
// when it ended up, made from the gateway's on-robot log and the base camp's recording.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/drop_reason.hpp"

namespace tgw::basecamp {

/// Where the samples of one topic ended up.
struct TopicFates {
    std::string topic;
    std::uint64_t received = 0;            ///< recorded at the base camp, matched to a robot row or not
    std::uint64_t received_unmatched = 0;  ///< of `received`, in no row of the robot log (robot columns NULL)
    std::optional<std::uint64_t> on_time;  ///< of `received`, within the recording's Lifespan (the TTL); empty
                                           ///< when the recording knows no Lifespan of the topic
    std::array<std::uint64_t, core::DROP_REASON_COUNT> dropped{};  ///< dropped on the robot, by logged reason
    std::uint64_t dropped_other = 0;                               ///< dropped with a reason this build does not know
    std::uint64_t lost = 0;  ///< written to the WAN by the gateway, never recorded at the base camp
    /// Of the dropped, those the camp's archive got later by backfill (docs/design/backfill.md): their rows keep
    /// fate `dropped` and their reason, with the archive's receive time and `backfilled` = 1.
    std::uint64_t backfilled = 0;

    std::uint64_t dropped_total() const;
    /// Archive rows of the topic: received + dropped + lost.
    std::uint64_t produced() const;
};

/// What a merge wrote, per topic (by name) and in total (topic "total").
struct MergeCounts {
    std::vector<TopicFates> topics;
    TopicFates total;
};

/// Merges the gateway's on-robot log (`telemetry-gateway --log`, with its forwarded_samples table) and a
/// base-camp recording (`tm-basecamp record|relay --out`) into the SQLite file `out`: one row per sample in
/// table `mission_samples`, fate `received` (receive time, latency), `dropped` (the log's reason) or `lost`, in an
/// order that depends only on the inputs, so merging again gives the same rows; plus a `meta` table naming the
/// inputs. A forwarded row matches a recorded sample of the same topic, source time, instance key and payload
/// size, duplicates by multiplicity; a recorded sample that matches none is kept as received with the robot's
/// columns NULL. A sample backfilled from this log is `dropped` with its row's reason and the recording's receive
/// time, backfilled 1; one whose row the log freed once the camp had acknowledged it (at --log-max-mib) keeps the
/// reason the recording stored, the robot's columns NULL. Another log's backfilled samples are not this robot's
/// and are left out. The gateway's own topics (tgw/status, tgw/receiver_report) are left out.
///
/// The archive is written to a temporary file next to `out` and renamed into place at the end: `out` is either
/// the previous archive or the whole new one. When `stop` turns true the merge stops, removes its temporary file
/// and returns nothing, `out` untouched. Throws base::ConfigError naming the file for an input that is missing,
/// unreadable or not what it should be, for an `out` that exists and is not a mission archive, and when the
/// archive cannot be written.
std::optional<MergeCounts> merge_mission(const std::string& robot_log, const std::string& recording,
                                         const std::string& out, const std::atomic<bool>* stop = nullptr);

}  // namespace tgw::basecamp
