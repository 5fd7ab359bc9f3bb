// The gateway's status (idl/GatewayStatus.idl) as it leaves: its rows from the per-topic accounting, and the
// sample it travels in.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "GatewayStatus.h"
#include "base/time.hpp"
#include "core/sample.hpp"
#include "core/urgency_demand.hpp"
#include "gateway/dds/topic_accounting.hpp"

namespace tgw::dds {

/// A row's TTL as the status carries it: whole milliseconds, zero for the retired topics' row.
std::uint32_t status_ttl_ms(const TopicCount& row);
/// How long `c`'s topic has had samples at `now`, in whole milliseconds as the status tells it; 0 before any.
std::uint32_t active_ms(const core::TopicCounters& c, base::SteadyTime now);
/// The rows as the base camp's grantor reads them from the status (core::DemandWatch compares them).
std::vector<core::TopicLoad> loads_of(const std::vector<TopicCount>& rows, base::SteadyTime now);
/// Appends a TopicStatus per row to `status`, a bridged topic under its WAN name (the name the base camp records
/// it as); returns the base-camp readers the rows have matched.
std::int32_t add_topic_rows(idl::GatewayStatus& status, const std::vector<TopicCount>& rows,
                            const std::string& robot_name, base::SteadyTime now);
/// `status` serialized into `sample`, keyed by its gateway; `compressed` (compact mode): as one zstd frame, which
/// the relay decompresses (its counters are mostly zeros and small numbers: 664 bytes of a paper robot's status
/// became 159 to 240). False if it could not be.
bool status_sample(idl::GatewayStatus& status, bool compressed, core::Sample& sample);

}  // namespace tgw::dds
