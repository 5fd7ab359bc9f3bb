#include "basecamp/channel_grantor.hpp"

#include <cstdio>
#include <cstring>
#include <exception>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "ChannelGrantPubSubTypes.h"
#include "GatewayStatusPubSubTypes.h"
#include "base/config_error.hpp"
#include "gateway/dds/channel_grant_topic.hpp"
#include "gateway/dds/status_topic.hpp"

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
                                      t.forwarded_wire_bytes(), t.queued_samples(), t.queued_bytes()});
    }
    return out;
}

}  // namespace

ChannelGrantor::ChannelGrantor(fdds::DomainParticipant* wan, double channel_bps, const base::Clock& clock)
    : wan_(wan), clock_(clock), shares_(core::ChannelShares::Config{STALE_AFTER, FLOOR_BPS}, clock) {
    shares_.set_capacity(channel_bps);
    fdds::TypeSupport type(new idl::ChannelGrantPubSubType());
    fdds::Topic* topic = nullptr;
    fdds::Publisher* publisher = nullptr;
    if (wan_->register_type(type) == ReturnCode_t::RETCODE_OK) {
        topic = wan_->create_topic(dds::CHANNEL_GRANT_TOPIC, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
        publisher = wan_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    }
    if (topic != nullptr && publisher != nullptr) {
        fdds::DataWriterQos qos = publisher->get_default_datawriter_qos();
        // Best effort, the latest per gateway: each grant says all there is, and the next comes within a second.
        qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
        qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
        qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        qos.history().depth = 1;
        qos.data_sharing().off();
        writer_ = publisher->create_datawriter(topic, qos);
    }
    if (writer_ == nullptr)
        throw base::ConfigError("--channel-rate: cannot create the writer of " + std::string(dds::CHANNEL_GRANT_TOPIC));
    next_grant_ = clock_.now();
}

ChannelGrantor::~ChannelGrantor() {
    if (writer_ != nullptr)
        const_cast<fdds::Publisher*>(writer_->get_publisher())->delete_datawriter(writer_);
}

void ChannelGrantor::take_status(const std::vector<std::uint8_t>& payload) {
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
    now.topics = loads(status);
    const std::string key = hex(now.prefix);

    std::lock_guard<std::mutex> lock(mutex_);
    if (!now.robot.empty() && statuses_.count(key) == 0) {
        // The robot's gateway restarted (a new participant): its old one's share would stand idle until stale.
        for (auto old = statuses_.begin(); old != statuses_.end();) {
            if (old->second.robot == now.robot) {
                shares_.forget(old->first);
                old = statuses_.erase(old);
            } else {
                ++old;
            }
        }
    }
    const auto it = statuses_.find(key);
    if (it != statuses_.end() && now.sent_ns <= it->second.sent_ns)
        return;  // a repeat, or older than what we have
    // A gateway makes its first status one status period after it starts: its counts since then are its arrivals
    // over at least that long (more, if the status waited for the link: the next status corrects it). On a slow
    // link statuses come seldom (STATUS_RATE_SHARE), so the share holds for three of the gateway's periods.
    const base::Duration period =
        std::max<base::Duration>(base::from_seconds(status.status_period_s()), std::chrono::seconds(1));
    const std::vector<core::TopicLoad> none;
    const std::vector<core::TopicLoad>& before = it != statuses_.end() ? it->second.topics : none;
    const base::Duration elapsed =
        it != statuses_.end() ? std::chrono::nanoseconds(now.sent_ns - it->second.sent_ns) : period;
    // Its floor: room for its next status (this one's size) and its most urgent sample, each within its TTL.
    const std::size_t status_wire_bytes = wire_.wire_bytes(payload.size());
    const double floor_bps = core::least_share_bps(now.topics, status_wire_bytes, dds::STATUS_TTL, wire_);
    // Its next status may come later than it said: its spacing follows its rate, and the grant is its rate now.
    base::Duration spacing = period;
    if (const auto granted = last_grants_.find(key); granted != last_grants_.end() && granted->second > 0) {
        spacing = std::max(spacing, std::chrono::duration_cast<base::Duration>(dds::status_rate_spacing(
                                        8.0 * static_cast<double>(status_wire_bytes), granted->second)));
    }
    shares_.report(key, core::urgency_demand(before, now.topics, elapsed, wire_),
                   std::max<base::Duration>(STALE_AFTER, 3 * spacing), floor_bps);
    statuses_[key] = std::move(now);
}

void ChannelGrantor::poll() {
    if (clock_.now() < next_grant_)
        return;
    next_grant_ = clock_.now() + GRANT_PERIOD;
    std::lock_guard<std::mutex> lock(mutex_);
    last_grants_ = shares_.grants();
    const auto sent_ns = static_cast<std::uint64_t>(base::to_ns(clock_.wall_now()));
    for (const auto& [key, bps] : last_grants_) {
        const auto heard = statuses_.find(key);
        if (heard == statuses_.end())
            continue;
        idl::ChannelGrant grant;
        std::copy(heard->second.prefix.begin(), heard->second.prefix.end(), grant.gateway_prefix().begin());
        grant.rate_bps(bps);
        grant.valid_ms(static_cast<std::uint32_t>(dds::GRANT_VALIDITY.count()));
        grant.sent_ns(sent_ns);
        writer_->write(&grant);
    }
}

core::ChannelGrants ChannelGrantor::last_grants() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return last_grants_;
}

}  // namespace tgw::basecamp
