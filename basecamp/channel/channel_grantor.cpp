#include "basecamp/channel/channel_grantor.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "ChannelGrantPubSubTypes.h"
#include "GatewayStatusPubSubTypes.h"
#include "base/config_error.hpp"
#include "basecamp/capture/latest_per_gateway_qos.hpp"
#include "wire/channel_grant_topic.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

namespace {

std::string hex(const std::array<std::uint8_t, 12>& prefix) {
    std::string out;
    char byte[3];
    for (std::uint8_t b : prefix) {
        std::snprintf(byte, sizeof byte, "%02x", b);
        out += byte;
    }
    return out;
}

std::vector<core::TopicLoad> loads(const idl::GatewayStatus& status) {
    std::vector<core::TopicLoad> out;
    for (const idl::TopicStatus& t : status.topics()) {
        out.push_back(core::TopicLoad{t.name(), std::chrono::milliseconds(t.ttl_ms()), t.received(), t.forwarded(),
                                      t.forwarded_wire_bytes(), t.queued_samples(), t.queued_bytes(),
                                      t.forwarded_bytes(), std::chrono::milliseconds(t.active_ms())});
    }
    return out;
}

}  // namespace

ChannelGrantor::ChannelGrantor(fdds::DomainParticipant* wan, double channel_bps, const base::Clock& clock,
                               ChannelMeter* meter, const DeliveryTally* tally, SampleConsumer* record)
    : wan_(wan),
      clock_(clock),
      channel_bps_(channel_bps),
      meter_(meter),
      tally_(tally),
      record_(record),
      shares_(core::ChannelShares::Config{STALE_AFTER, FLOOR_BPS}, clock) {
    // The robots' grants leave the newcomers' share free (core::JOIN_SHARE): a robot that joins, or whose gateway
    // restarts, sends within it until its first own grant.
    shares_.set_capacity((1.0 - core::JOIN_SHARE) * channel_bps);
    fdds::TypeSupport type(new idl::ChannelGrantPubSubType());
    fdds::Topic* topic = nullptr;
    fdds::Publisher* publisher = nullptr;
    if (wan_->register_type(type) == ReturnCode_t::RETCODE_OK) {
        topic = wan_->create_topic(wire::CHANNEL_GRANT_TOPIC, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
        publisher = wan_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    }
    if (topic != nullptr && publisher != nullptr) {
        // The latest per gateway: each grant says all there is, and the next comes within a second.
        writer_ = publisher->create_datawriter(topic, latest_per_gateway_qos(*publisher));
    }
    if (writer_ == nullptr)
        throw base::ConfigError("--channel-rate: cannot create the writer of " +
                                std::string(wire::CHANNEL_GRANT_TOPIC));
    next_grant_ = clock_.now();
}

ChannelGrantor::~ChannelGrantor() {
    if (writer_ != nullptr)
        const_cast<fdds::Publisher*>(writer_->get_publisher())->delete_datawriter(writer_);
}

void ChannelGrantor::take_status(const std::vector<std::uint8_t>& payload, std::size_t sent_bytes) {
    idl::GatewayStatusPubSubType type;
    idl::GatewayStatus status;
    eprosima::fastrtps::rtps::SerializedPayload_t serialized(static_cast<std::uint32_t>(payload.size()));
    std::memcpy(serialized.data, payload.data(), payload.size());
    serialized.length = static_cast<std::uint32_t>(payload.size());
    try {
        if (!type.deserialize(&serialized, &status))
            return;
    } catch (const std::exception&) {
        return;  // malformed: the relay has passed it on as it came; nothing to learn from it here
    }
    Heard now;
    std::copy(status.gateway_prefix().begin(), status.gateway_prefix().end(), now.prefix.begin());
    now.robot = status.robot_name();
    now.sent_ns = status.sent_ns();
    now.unscheduled_wire_bytes = status.unscheduled_wire_bytes();
    now.topics = loads(status);
    now.uplink_topics = status.uplink_topics();
    now.uplink_charged = status.uplink_charged();
    // The camp counts its commands as it sends them (count_commands()): not again in its traffic outside the schedule.
    const std::uint64_t uplink_charged_bytes = now.uplink_charged ? status.uplink_wire_bytes() : 0;
    if (now.unscheduled_wire_bytes >= uplink_charged_bytes)
        now.unscheduled_wire_bytes -= uplink_charged_bytes;
    const std::string key = hex(now.prefix);
    if (meter_ != nullptr)
        meter_->gateway(now.prefix);  // its datagrams cross the channel

    std::lock_guard<std::mutex> lock(mutex_);
    if (!now.robot.empty() && statuses_.count(key) == 0) {
        // The robot's gateway restarted (a new participant): its old one's share would stand idle until stale.
        for (auto old = statuses_.begin(); old != statuses_.end();) {
            if (!old->second.empty() && old->second.back().robot == now.robot) {
                shares_.forget(old->first);
                old = statuses_.erase(old);
            } else {
                ++old;
            }
        }
    }
    std::deque<Heard>& heard = statuses_[key];
    if (!heard.empty() && now.sent_ns <= heard.back().sent_ns)
        return;  // a repeat, or older than what we have
    // The demand over core::DEMAND_WINDOW at least: from the newest status that much older, else the oldest kept.
    // Between two statuses in a row, often under a second apart, a few samples more or less swung the grants.
    const std::uint64_t window_ns = static_cast<std::uint64_t>(std::chrono::nanoseconds(core::DEMAND_WINDOW).count());
    const Heard* earlier = heard.empty() ? nullptr : &heard.front();
    for (const Heard& h : heard) {
        if (now.sent_ns - h.sent_ns >= window_ns)
            earlier = &h;
    }
    // A gateway's first status tells what waits in its queue, not what arrives: its counts gathered over however
    // long it took the status to cross (seconds, for a gateway restarted in a busy fleet), and read as one
    // period's they made the newcomer's demand several times what it was, and its grant starved the others'
    // hazards. Its next status, DEMAND_WINDOW later, tells its arrivals. On a slow link statuses come seldom
    // (STATUS_RATE_SHARE), so the share holds for three of the gateway's periods.
    const base::Duration period =
        std::max<base::Duration>(base::from_seconds(status.status_period_s()), std::chrono::seconds(1));
    const std::vector<core::TopicLoad>& before = earlier != nullptr ? earlier->topics : now.topics;
    const base::Duration elapsed =
        earlier != nullptr ? std::chrono::nanoseconds(now.sent_ns - earlier->sent_ns) : period;
    // What its traffic outside the schedule took since then.
    const double unscheduled_bps =
        earlier != nullptr && now.unscheduled_wire_bytes >= earlier->unscheduled_wire_bytes
            ? 8.0 * static_cast<double>(now.unscheduled_wire_bytes - earlier->unscheduled_wire_bytes) /
                  base::to_seconds(elapsed)
            : 0.0;
    const core::AloneWire alone{wire_, status.compact_wan()};
    const std::size_t status_wire_bytes = alone.wire_bytes(sent_bytes, true);
    // Its next status may come later than it said: its spacing follows its rate, and the grant is its rate now.
    base::Duration spacing = period;
    if (const auto granted = last_grants_.find(key); granted != last_grants_.end() && granted->second > 0) {
        spacing = std::max(spacing, std::chrono::duration_cast<base::Duration>(wire::status_rate_spacing(
                                        8.0 * static_cast<double>(status_wire_bytes), granted->second)));
    }
    // Its floor (core::least_share_bps): room for its next status (this one's size as serialized, as the gateway
    // sizes its own floor, not as a compact gateway compressed it) within its TTL, and for that
    // status beside its most urgent sample within the sample's TTL, once over (a gateway without a grant of its own
    // budgets twice that, core::NEWCOMER_LEAST_SHARE_FACTOR), and for its traffic outside the schedule since then,
    // which its budget pays first, over the part of its rate it budgets.
    // Twice over here held back another robot's hazards (two robots at 30,000 bit/s: 274 of 300 on time, against
    // 295 once over). Within the status's TTL of a second, not its Lifespan: a floor a fifth as large let the grants
    // swing below what a robot's A and B needed (three robots at 60,000 bit/s: 41 and 109 of 200 A on time in two
    // runs, against 200 and 200).
    const double budget_fraction = status.sensed_rate_bps() > 0 ? status.budget_bps() / status.sensed_rate_bps() : 1.0;
    now.budget_fraction = budget_fraction > 0 && budget_fraction <= 1.0 ? budget_fraction : 1.0;
    const double floor_bps =
        core::least_share_bps(now.topics, payload.size(), wire::STATUS_TTL, alone, budget_fraction, unscheduled_bps);
    shares_.report(key,
                   core::grantable_demand(core::urgency_demand(before, now.topics, elapsed, wire_), unscheduled_bps,
                                          budget_fraction),
                   std::max<base::Duration>(STALE_AFTER, 3 * spacing), floor_bps);
    heard.push_back(std::move(now));
    while (heard.size() > 1 && heard.back().sent_ns - heard[1].sent_ns >= window_ns)
        heard.pop_front();
    status_heard_.store(true);
}

void ChannelGrantor::commands_sent(const std::vector<passthrough::UplinkCount>& counts) {
    const base::SteadyTime now = clock_.now();
    std::lock_guard<std::mutex> lock(mutex_);
    for (const passthrough::UplinkCount& up : counts) {
        Sent& sent = sent_[up.from_topic];
        sent.rate.update(now, up.wire_bytes);
        sent.ttl = up.ttl ? std::optional<base::Duration>(up.ttl->ttl) : std::nullopt;
        if (meter_ != nullptr && up.wire_bytes > sent.wire_bytes && charged(up.from_topic))
            meter_->camp_sent(up.wire_bytes - sent.wire_bytes);
        sent.wire_bytes = up.wire_bytes;
    }
}

bool ChannelGrantor::charged(const std::string& topic) const {
    return std::any_of(statuses_.begin(), statuses_.end(), [&](const auto& gateway) {
        const std::deque<Heard>& heard = gateway.second;
        return !heard.empty() && heard.back().uplink_charged &&
               std::find(heard.back().uplink_topics.begin(), heard.back().uplink_topics.end(), topic) !=
                   heard.back().uplink_topics.end();
    });
}

bool ChannelGrantor::count_commands() {
    const base::SteadyTime now = clock_.now();
    bool moved = false;
    camp_now_.clear();
    for (const auto& [key, heard] : statuses_) {
        if (heard.empty())
            continue;
        const Heard& last = heard.back();
        // At the commands' most urgent TTL; one without a TTL ranks first, for it leaves whatever the grants say.
        core::UrgencyDemand camp{base::Duration::max(), 0.0};
        for (const std::string& topic : last.uplink_topics) {
            const auto it = sent_.find(topic);
            if (!last.uplink_charged || it == sent_.end())
                continue;
            camp.bps += it->second.rate.bps(now);
            camp.ttl = std::min(camp.ttl, it->second.ttl.value_or(base::Duration{}));
        }
        camp.bps /= last.budget_fraction;
        shares_.set_camp_traffic(key, camp);
        camp_now_[key] = camp;
        std::vector<core::UrgencyDemand> granted;
        if (const auto it = camp_granted_.find(key); it != camp_granted_.end())
            granted.push_back(it->second);
        const core::DemandWatch::Config watch;  // as a gateway tells its own demand's moves
        moved = moved || core::demand_changed(granted, {camp}, watch.fraction, watch.floor_bps);
    }
    return moved;
}

void ChannelGrantor::arrived(const ParticipantPrefix& sender, base::Duration one_way, std::size_t payload_bytes) {
    if (meter_ != nullptr)
        meter_->stamped_sample(sender, one_way, wire_.wire_bytes(payload_bytes));
}

std::optional<ChannelReading> ChannelGrantor::measure_channel() {
    if (meter_ == nullptr)
        return std::nullopt;
    std::uint64_t lost = 0;
    if (tally_ != nullptr) {
        for (const auto& [prefix, totals] : tally_->totals())
            lost += totals.lost_samples;
    }
    double granted = 0;
    for (const auto& [key, bps] : last_grants_)
        granted += bps;
    const ChannelReading reading = meter_->measure(lost, granted);
    channel_bps_ = reading.channel_bps;
    shares_.set_capacity((1.0 - core::JOIN_SHARE) * channel_bps_);
    if (reading.verdict != channel_verdict_) {
        // Each change of what it finds, not each second: a line to read when the grants look wrong.
        channel_verdict_ = reading.verdict;
        std::fprintf(stderr, "tm-basecamp relay: channel %s: sharing %.0f bit/s\n", core::to_string(reading.verdict),
                     channel_bps_);
    }
    return reading;
}

void ChannelGrantor::poll() {
    const bool heard = status_heard_.exchange(false);
    std::lock_guard<std::mutex> lock(mutex_);
    const bool commands_moved = count_commands();
    if (!heard && !commands_moved && clock_.now() < next_grant_)
        return;
    next_grant_ = clock_.now() + GRANT_PERIOD;
    const std::optional<ChannelReading> reading = measure_channel();
    last_grants_ = shares_.grants();
    camp_granted_ = camp_now_;
    const auto sent_ns = static_cast<std::uint64_t>(base::to_ns(clock_.wall_now()));
    ChannelRecord round = channel_record(sent_ns, reading);
    for (const auto& [key, bps] : last_grants_) {
        const auto heard = statuses_.find(key);
        const bool known = heard != statuses_.end() && !heard->second.empty();
        if (known)
            write_grant(heard->second.back().prefix, bps, sent_ns);
        if (record_ != nullptr)
            round.grants.push_back(GrantRecord{key, known ? heard->second.back().robot : "", bps});
    }
    // Not more: several gateways may join at once (a fleet starting). Granting them also what the robots known
    // left unclaimed (all of the channel at the start) let three newcomers send three channels' worth at once.
    write_grant(wire::NEWCOMER_PREFIX, core::JOIN_SHARE * channel_bps_, sent_ns);
    if (record_ != nullptr)
        record_->add_channel(round);
}

ChannelRecord ChannelGrantor::channel_record(std::uint64_t sent_ns,
                                             const std::optional<ChannelReading>& reading) const {
    ChannelRecord out;
    out.time_ns = static_cast<std::int64_t>(sent_ns);
    out.channel_bps = channel_bps_;
    out.newcomer_bps = core::JOIN_SHARE * channel_bps_;
    if (reading) {
        out.verdict = core::to_string(reading->verdict);
        out.delivered_bps = reading->delivered_bps;
        if (reading->queueing)
            out.queueing_ns = reading->queueing->count();
    }
    return out;
}

void ChannelGrantor::write_grant(const Prefix& prefix, double bps, std::uint64_t sent_ns) {
    idl::ChannelGrant grant;
    std::copy(prefix.begin(), prefix.end(), grant.gateway_prefix().begin());
    grant.rate_bps(bps);
    grant.valid_ms(static_cast<std::uint32_t>(wire::GRANT_VALIDITY.count()));
    grant.sent_ns(sent_ns);
    writer_->write(&grant);
}

double ChannelGrantor::newcomer_share() const {
    return core::JOIN_SHARE * channel_bps();
}

double ChannelGrantor::channel_bps() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return channel_bps_;
}

std::optional<ChannelReading> ChannelGrantor::channel_reading() const {
    return meter_ != nullptr ? std::optional<ChannelReading>(meter_->reading()) : std::nullopt;
}

core::ChannelGrants ChannelGrantor::last_grants() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return last_grants_;
}

}  // namespace tgw::basecamp
