#include "gateway/dds/status_message.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <utility>

#include "GatewayStatusPubSubTypes.h"
#include "base/robot_namespace.hpp"
#include "compact/zstd_frame.hpp"
#include "gateway/dds/keyed_sample.hpp"

namespace tgw::dds {

std::uint32_t status_ttl_ms(const TopicCount& row) {
    return row.bridged
               ? static_cast<std::uint32_t>(std::chrono::duration_cast<std::chrono::milliseconds>(row.ttl.ttl).count())
               : 0u;
}

std::uint32_t active_ms(const core::TopicCounters& c, base::SteadyTime now) {
    if (!c.first_received || *c.first_received > now) {
        return 0;
    }
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now - *c.first_received).count();
    return static_cast<std::uint32_t>(std::min<std::int64_t>(ms, std::numeric_limits<std::uint32_t>::max()));
}

std::vector<core::TopicLoad> loads_of(const std::vector<TopicCount>& rows, base::SteadyTime now) {
    std::vector<core::TopicLoad> loads;
    for (const TopicCount& row : rows) {
        const core::TopicCounters& c = row.counters;
        loads.push_back(core::TopicLoad{row.name, std::chrono::milliseconds(status_ttl_ms(row)), c.received,
                                        c.forwarded, c.forwarded_wire_bytes, c.queued, c.queued_payload_bytes,
                                        c.forwarded_payload_bytes, std::chrono::milliseconds(active_ms(c, now))});
    }
    return loads;
}

std::int32_t add_topic_rows(idl::GatewayStatus& status, const std::vector<TopicCount>& rows,
                            const std::string& robot_name, base::SteadyTime now) {
    std::int32_t matched_readers = 0;
    for (const TopicCount& row : rows) {
        const core::TopicCounters& c = row.counters;
        idl::TopicStatus t;
        t.name(row.bridged ? base::namespaced_topic(robot_name, row.name) : row.name);
        t.ttl_ms(status_ttl_ms(row));
        t.queued_samples(static_cast<std::uint32_t>(c.queued));
        t.queued_bytes(c.queued_payload_bytes);
        t.received(c.received);
        t.forwarded(c.forwarded);
        t.forwarded_wire_bytes(c.forwarded_wire_bytes);
        t.forwarded_bytes(c.forwarded_payload_bytes);
        t.expired(c.dropped_for(core::DropReason::expired));
        t.doomed(c.dropped_for(core::DropReason::doomed));
        t.evicted(c.dropped_for(core::DropReason::evicted));
        t.oversize(c.dropped_for(core::DropReason::oversize));
        t.shutdown(c.dropped_for(core::DropReason::shutdown));
        t.write_failed(c.dropped_for(core::DropReason::write_failed));
        t.no_reader(c.dropped_for(core::DropReason::no_reader));
        t.rate_capped(c.dropped_for(core::DropReason::rate_capped));
        t.superseded(c.dropped_for(core::DropReason::superseded));
        t.matched_readers(row.matched_readers);
        t.active_ms(active_ms(c, now));
        matched_readers += t.matched_readers();
        status.topics().push_back(std::move(t));
    }
    return matched_readers;
}

bool status_sample(idl::GatewayStatus& status, bool compressed, core::Sample& sample) {
    idl::GatewayStatusPubSubType type;
    if (!keyed_sample(type, status, sample)) {
        return false;
    }
    if (!compressed) {
        return true;
    }
    std::vector<std::uint8_t> frame;
    if (!compact::zstd_frame(sample.payload.data(), sample.payload.size(), frame)) {
        return false;
    }
    sample.payload = std::move(frame);
    return true;
}

}  // namespace tgw::dds
