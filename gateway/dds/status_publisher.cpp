#include "gateway/dds/status_publisher.hpp"

#include <algorithm>
#include <utility>

#include "GatewayStatusPubSubTypes.h"
#include "core/alone_wire.hpp"
#include "core/urgency_demand.hpp"
#include "gateway/dds/status_message.hpp"
#include "wire/status_topic.hpp"

namespace tgw::dds {

StatusPublisher::StatusPublisher(Config config, core::ForwardingLoop& loop, core::TopicId topic,
                                 const base::Clock& clock, Sources sources)
    : config_(std::move(config)), loop_(loop), topic_(topic), clock_(clock), sources_(std::move(sources)) {
    if (config_.channel_grants) {
        // The grantor's own wire model (the default one): the watch works the demand out as the grantor does.
        demand_watch_.emplace(core::DemandWatch::Config{}, core::WireModel{});
    }
}

base::Duration StatusPublisher::spacing(double rate_bps, double wire_bits) const {
    // At most STATUS_RATE_SHARE of the rate: a status and its headers on the wire, alone in a datagram.
    if (rate_bps <= 0) {
        return config_.period;
    }
    return std::max(config_.period,
                    std::chrono::duration_cast<base::Duration>(wire::status_rate_spacing(wire_bits, rate_bps)));
}

bool StatusPublisher::demand_moved(std::chrono::steady_clock::time_point now, double rate_bps,
                                   std::optional<std::vector<TopicCount>>& rows, std::vector<core::TopicLoad>& loads) {
    if (demand_watch_->pending()) {
        // The last status left, or was dropped (past its TTL in the queue), since it was made.
        const core::TopicCounters c = loop_.counters(topic_);
        if (c.forwarded > forwarded_seen_) {
            demand_watch_->delivered(true, now);
        } else if (c.received - c.forwarded - c.queued > dropped_seen_) {
            demand_watch_->delivered(false, now);
        }
    }
    rows = sources_.rows();
    loads = loads_of(*rows, clock_.now());
    return demand_watch_->changed(now, loads, rate_bps);  // changed() sees every period's counts
}

void StatusPublisher::look(std::chrono::steady_clock::time_point now) {
    const double rate = loop_.rate_bps();
    std::optional<std::vector<TopicCount>> rows;
    std::vector<core::TopicLoad> loads;
    bool due = !last_at_ || now - *last_at_ >= std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                   spacing(rate, last_wire_bits_));
    if (demand_watch_) {
        due = demand_moved(now, rate, rows, loads) || due;
    }
    if (!due) {
        return;
    }
    if (demand_watch_) {
        const core::TopicCounters c = loop_.counters(topic_);
        forwarded_seen_ = c.forwarded;
        dropped_seen_ = c.received - c.forwarded - c.queued;
    }

    idl::GatewayStatus status;
    const base::SteadyTime made_at = clock_.now();
    status.robot_name(config_.robot_name);
    status.compact_wan(config_.compact_wan);
    status.sent_ns(static_cast<std::uint64_t>(base::to_ns(clock_.wall_now())));
    status.sensed_rate_bps(rate);
    status.budget_bps(rate * config_.budget_fraction);
    if (!rows) {
        rows = sources_.rows();
    }
    const std::int32_t rows_readers = add_topic_rows(status, *rows, config_.robot_name, made_at);
    sources_.fill(status, rows_readers);

    core::Sample sample;
    // Made twice: its period, a field of its own, follows from its size.
    bool made = status_sample(status, config_.compact_wan, sample);
    idl::GatewayStatusPubSubType type;
    const std::size_t bytes = made ? sample.payload.size() : type.getSerializedSizeProvider(&status)();
    const double wire_bits = static_cast<double>(config_.wire.wire_bits(bytes));
    status.status_period_s(base::to_seconds(spacing(rate, wire_bits)));
    made = made && status_sample(status, config_.compact_wan, sample);
    last_at_ = now;
    last_wire_bits_ = wire_bits;
    if (demand_watch_) {
        demand_watch_->sent(now, loads, wire_bits);
        // Before the status goes to the loop: a grant too small for it would keep the base camp from ever
        // hearing of the demand that should raise the grant. Once over, as the base camp grants it (the rule
        // doubles it before the first grant: core::granted_rate_bps). Not with the traffic outside the schedule
        // over the last status period, as the grantor adds it over 2 s: a burst of repairs made this floor, and
        // the gateway's rate, exceed its grant (ChannelGrantTest: two gateways 31,016 bit/s of a 30,000 channel).
        // The status as serialized, not as compressed: with the floor of a compressed one (4,176 bit/s for a
        // paper robot) a robot that starts publishing after the others had its B expire for the 2 s until its
        // demand reached the base camp (three robots, measured channel: B 190 and 192 of 200 in 2 of 5 runs); the
        // floor of the serialized one (about 10,000) carries a robot's A and B meanwhile.
        sources_.least_share(core::least_share_bps(loads, type.getSerializedSizeProvider(&status)(), wire::STATUS_TTL,
                                                   core::AloneWire{config_.wire, config_.compact_wan},
                                                   config_.budget_fraction));
    }

    if (made) {
        sample.topic = topic_;
        sample.source_time = clock_.wall_now();
        // Counted first: the loop may write it, and a reader have it, before submit returns.
        published_.fetch_add(1, std::memory_order_relaxed);
        loop_.submit(std::move(sample));
    } else if (demand_watch_) {
        demand_watch_->delivered(false, now);  // never queued: no count would ever say what became of it
    }
}

}  // namespace tgw::dds
