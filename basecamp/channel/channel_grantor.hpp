// The base camp's side of a fleet's shared channel (tm-basecamp relay --channel-rate): each gateway's share.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <vector>

#include "base/clock.hpp"
#include "basecamp/capture/delivery_tally.hpp"
#include "basecamp/channel/channel_meter.hpp"
#include "basecamp/sample/sample_consumer.hpp"
#include "core/channel_shares.hpp"
#include "core/demand_watch.hpp"
#include "core/granted_rate.hpp"
#include "core/sent_rate.hpp"
#include "core/urgency_demand.hpp"
#include "passthrough/uplink.hpp"

namespace eprosima::fastdds::dds {
class DataWriter;
class DomainParticipant;
}  // namespace eprosima::fastdds::dds

namespace tgw::basecamp {

/// Reads each gateway's status as the relay takes it off the WAN, works out from two in a row what the robot needs
/// by urgency (core::urgency_demand), and once a GRANT_PERIOD grants each gateway its share of the channel
/// (core::split_channel: a floor, each robot's own where it needs more (core::least_share_bps: room for its
/// status and its most urgent sample), then the fleet's shortest TTLs first) on wire::CHANNEL_GRANT_TOPIC, keyed
/// by the gateway's prefix. core::JOIN_SHARE of the channel is kept out of them and granted to any gateway without
/// a grant of its own (the newcomers' share, wire::NEWCOMER_PREFIX). A gateway silent for long (STALE_AFTER) has no
/// share until its next status, and meanwhile budgets for the newcomers' share. A status of a named robot from a
/// new gateway (restarted) ends the old gateway's share at once. With a ChannelMeter, the channel's rate is measured
/// (what arrives, what is lost and how long it took) with --channel-rate its upper bound.
class ChannelGrantor {
  public:
    static constexpr base::Duration GRANT_PERIOD = std::chrono::seconds(1);
    /// A gateway silent this long, or three of its status periods if longer, has no share until its next status.
    /// Long, because a silent gateway's share would go to the others while it, hearing no grant, falls back to its
    /// sensor: both would send as if the channel were theirs. A robot's statuses can be lost for a while (each
    /// expires behind a long sample on a small share); a gateway that restarted ends its old share at once.
    static constexpr base::Duration STALE_AFTER = std::chrono::seconds(30);
    /// Every gateway's floor: a status and discovery, and its first sample.
    static constexpr double FLOOR_BPS = 2000;

    /// Writes on `wan` (which must outlive it) a channel of `channel_bps`; with `meter` and `tally` (which must
    /// outlive it), a channel of what `meter` measures (`tally` counts the samples lost), `channel_bps` at most.
    /// Each round of grants goes to `record` (the relay's recording) too, where given. Throws base::ConfigError
    /// naming --channel-rate when DDS refuses the writer.
    ChannelGrantor(eprosima::fastdds::dds::DomainParticipant* wan, double channel_bps, const base::Clock& clock,
                   ChannelMeter* meter = nullptr, const DeliveryTally* tally = nullptr,
                   SampleConsumer* record = nullptr);
    ~ChannelGrantor();
    ChannelGrantor(const ChannelGrantor&) = delete;
    ChannelGrantor& operator=(const ChannelGrantor&) = delete;

    /// One sample of tgw/status as it came off the WAN (its serialized payload), `sent_bytes` of it on the WAN
    /// (a compact gateway's status travels compressed); any thread. A payload that does not decode is ignored.
    void take_status(const std::vector<std::uint8_t>& payload, std::size_t sent_bytes);

    /// A compact bundle of `payload_bytes` from the gateway `sender` came off the WAN `one_way` after its writer
    /// stamped it (the relay's clock less the gateway's); any thread. Counts only where the channel is measured.
    void arrived(const ParticipantPrefix& sender, base::Duration one_way, std::size_t payload_bytes);

    /// The relay's uplink counts now (`tm-basecamp relay --uplink`): what the camp sends each robot on the channel.
    /// A gateway whose status says its budget pays for its commands (`--duplex half`) is granted their rate on top
    /// of its floor and before any telemetry, from the next round on: they take the air whatever it is granted, and
    /// a grant without room for them starved its telemetry and the statuses that would have asked for more (rover1
    /// at 11,506 bit/s with 12,320 of commands: 37 of 200 A on time). The relay's thread, before poll().
    void commands_sent(const std::vector<passthrough::UplinkCount>& counts);

    /// Writes the grants when GRANT_PERIOD has passed since the last, or a status came since: a robot whose demand
    /// rose hears its grant at once (its gateway sends a status when its demand moves); the relay's thread.
    void poll();

    /// The grants last written, by gateway prefix (hex).
    core::ChannelGrants last_grants() const;
    /// The newcomers' share it writes (wire::NEWCOMER_PREFIX): core::JOIN_SHARE of the channel.
    double newcomer_share() const;
    /// What its meter found; nullopt when it does not measure the channel.
    std::optional<ChannelReading> channel_reading() const;

  private:
    using Prefix = std::array<std::uint8_t, 12>;
    struct Heard {
        Prefix prefix{};
        std::string robot;  ///< its --robot-name, or empty
        std::uint64_t sent_ns = 0;
        std::uint64_t unscheduled_wire_bytes = 0;  ///< cumulative: its traffic outside the schedule
        std::vector<core::TopicLoad> topics;
        std::vector<std::string> uplink_topics;  ///< its commands' names at the camp
        bool uplink_charged = false;             ///< its budget pays for them
        double budget_fraction = 1.0;            ///< what it budgets of its rate
    };
    /// What the camp sends on one uplink topic.
    struct Sent {
        core::SentRate rate;
        std::optional<base::Duration> ttl;
        std::uint64_t wire_bytes = 0;  ///< so far
    };

    /// Whether a gateway heard from pays for the camp's commands on `topic`; under mutex_.
    bool charged(const std::string& topic) const;
    /// Each gateway's commands, as the camp sends them now, into shares_. True when a gateway's moved by more than
    /// a quarter (and 1,000 bit/s) since the last grants: commands that begin must not wait for the next round,
    /// for they take the air at once. Under mutex_.
    bool count_commands();

    void write_grant(const Prefix& prefix, double bps, std::uint64_t sent_ns);
    /// This round's channel as the recording keeps it, its grants to be added; under mutex_.
    ChannelRecord channel_record(std::uint64_t sent_ns, const std::optional<ChannelReading>& reading) const;
    /// The channel's rate it shares now: --channel-rate, or what it measured.
    double channel_bps() const;
    /// The channel's measure, once an interval; nullopt where it is not measured. Under mutex_.
    std::optional<ChannelReading> measure_channel();

    eprosima::fastdds::dds::DomainParticipant* wan_;
    eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
    const base::Clock& clock_;
    const core::WireModel wire_;
    mutable std::mutex mutex_;
    double channel_bps_;                                                    // under mutex_
    core::ChannelVerdict channel_verdict_ = core::ChannelVerdict::unknown;  // under mutex_
    ChannelMeter* meter_;
    const DeliveryTally* tally_;
    SampleConsumer* record_;
    core::ChannelShares shares_;  // under mutex_
    /// Per gateway, its latest statuses: the newest at least core::DEMAND_WINDOW old, and those after it; under
    /// mutex_.
    std::map<std::string, std::deque<Heard>> statuses_;
    core::ChannelGrants last_grants_;   // under mutex_
    std::map<std::string, Sent> sent_;  // by the uplink topic's name; under mutex_
    /// By gateway: the camp's commands now, and as the last grants counted them; under mutex_.
    std::map<std::string, core::UrgencyDemand> camp_now_;
    std::map<std::string, core::UrgencyDemand> camp_granted_;
    base::SteadyTime next_grant_{};
    std::atomic<bool> status_heard_{false};  ///< a status came since the grants were last written
};

}  // namespace tgw::basecamp
