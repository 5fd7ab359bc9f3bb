#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include <fastdds/rtps/transport/TransportDescriptorInterface.h>
#include "base/clock.hpp"
#include "base/event_loop.hpp"
#include "base/quiet_discovery_ports.hpp"
#include "base/wan_address.hpp"
#include "core/demand_watch.hpp"
#include "core/forwarding_loop.hpp"
#include "core/latency_histogram.hpp"
#include "core/scheduler.hpp"
#include "core/sent_rate.hpp"
#include "gateway/dds/backfill_ack_reader.hpp"
#include "gateway/dds/backfill_sender.hpp"
#include "gateway/dds/coalescing_transport.hpp"
#include "gateway/dds/compact_wan.hpp"
#include "gateway/dds/datagram_coalescer.hpp"
#include "gateway/dds/gateway_config.hpp"
#include "gateway/dds/grant_reader.hpp"
#include "gateway/dds/peer_lookup.hpp"
#include "gateway/dds/rate_control.hpp"
#include "gateway/dds/receiver_report_reader.hpp"
#include "gateway/dds/repair_desk.hpp"
#include "gateway/dds/robot_transport.hpp"
#include "gateway/dds/status_publisher.hpp"
#include "gateway/dds/topic_accounting.hpp"
#include "gateway/dds/topic_bridge.hpp"
#include "gateway/dds/topic_filter.hpp"
#include "gateway/dds/topic_lifecycle.hpp"
#include "gateway/dds/topic_rules.hpp"
#include "passthrough/discovery.hpp"
#include "passthrough/offered_qos.hpp"
#include "passthrough/ttl_resolver.hpp"
#include "passthrough/uplink.hpp"
#include "passthrough/uplink_topics.hpp"
#include "sensor/rate_sensor.hpp"
#include "types/type_library.hpp"

namespace tgw::log {
class RobotLog;
}

namespace eprosima::fastdds::dds {
class DataWriter;
}

namespace tgw::dds {

class GatewaySink;
class RobotParticipant;
class TopicTable;
class WanRouter;

/// The whole gateway in one object (main stays thin; integration tests create it in-process): the on-robot
/// log, the WAN participant, the ForwardingLoop with its sink, and the robot participant whose discovery feeds
/// the TopicLifecycle (one TopicBridge per admitted topic, with a lane per QoS its publishers offer). It wires them,
/// applies the rate, publishes the status and stops them in order. Entities are created and deleted in a worker
/// thread of its own (base::EventLoop), never in Fast DDS's callbacks.
class Gateway {
  public:
    /// Starts everything. Throws base::ConfigError (bad flag, file, or a participant that cannot be created).
    Gateway(GatewayConfig config, const base::Clock& clock);
    ~Gateway();

    Gateway(const Gateway&) = delete;
    Gateway& operator=(const Gateway&) = delete;

    /// Stops reading the robot domain, writes everything still queued to the log as `shutdown` and flushes
    /// the log. The WAN participant stays until destruction. Idempotent.
    void stop();

    /// The link rate the scheduler budgets for, from the rate sensor.
    void set_rate(double rate_bps);
    /// Whether the WAN interface can carry anything (sensor::LinkStateWatch). While it cannot, the budget is 0
    /// whatever the sensor says: samples wait for the link, or go to the on-robot log as their TTL passes, and
    /// none is written into a dead interface and counted as forwarded. Up by default.
    void set_wan_link_up(bool up);
    bool wan_link_up() const { return rate_->link_up(); }
    /// The WAN interface has `address` now, another than the WAN participant's (a DHCP lease, a mesh radio): the
    /// participant is made anew on it (WanRouter::rebind), nothing scheduled meanwhile, and the uplink and the
    /// readers of reports and grants follow it. From any thread; done in the gateway's own, soon after.
    void rebind_wan(const std::string& address);
    /// The address the WAN participant is bound to; empty: every interface.
    std::string wan_interface_address() const;
    /// Times the WAN participant was made anew on another address.
    std::uint64_t wan_rebinds() const { return wan_rebinds_.load(); }
    /// What the rate sensor sees queued in the link now, in bytes.
    void observe_link_backlog(std::uint64_t bytes);
    /// A good reading of the rate sensor: its rate, and its view of the link's queue where it has one.
    void apply_reading(const sensor::RateReading& reading);
    /// The sensor's SPEC, for the status.
    void set_sensor_description(std::string description);
    /// Status samples made so far (each goes through the schedule; status_counters() says what became of them).
    std::uint64_t statuses_published() const { return status_ ? status_->published() : 0; }
    /// The status topic's counters in the schedule; all zero without --status-period.
    core::TopicCounters status_counters() const;
    /// What backfill did: its topic's counters in the schedule (each sample sent counts as forwarded), the sender's
    /// counts and the backlog; nullopt without backfill.
    struct BackfillSummary {
        core::TopicCounters counters;
        BackfillSender::Counts counts;
        core::BackfillPlanner::Backlog backlog;
    };
    std::optional<BackfillSummary> backfill_summary() const;
    /// The rate the scheduler budgets with (before its budget fraction).
    double rate_bps() const;
    /// The base camp's valid grant for this gateway (--channel-grants); nullopt without one.
    std::optional<double> granted_bps() const;

    /// The topics bridged now (a retired topic is not among them; see topic_counts()).
    std::vector<BridgedTopic> topics() const;
    /// Topics bridged now: each has a bridge, a scheduler slot and, in standard mode, a WAN topic.
    std::size_t bridged_topics() const;
    /// Topics the scheduler holds now: the bridged ones, and the status topic.
    std::size_t scheduled_topics() const;
    /// Topics the WAN participant has writers of now (the status topic's included; compact mode: its two).
    std::size_t wan_topics() const;
    /// Lanes Fast DDS refused to make (their WAN writer or robot reader; each logged when it happened): their
    /// publishers' samples are not bridged, and nothing of the refused lane stays.
    std::uint64_t refused_lanes() const { return lifecycle_->refused_lanes(); }
    /// Per topic name, what became of its samples, over every bridge it had: the topics bridged now, by name, then
    /// the retired ones, by name.
    std::vector<TopicCount> topic_counts() const;
    std::optional<BridgedTopic> find_topic(const std::string& name) const;
    /// Waits until `name` is bridged (reader and WAN writer exist); false on timeout.
    bool wait_for_topic(const std::string& name, std::chrono::milliseconds timeout) const;

    /// The counts of the topic bridged under `id` now (BridgedTopic::id): once a topic is retired its id may be
    /// another topic's, and its counts are in topic_counts().
    core::TopicCounters counters(core::TopicId id) const;
    /// Every topic's counts together, retired topics' included.
    core::TopicCounters total_counters() const;
    std::size_t queued_samples() const;

    std::int32_t robot_matched_writers(core::TopicId id) const;
    std::int32_t wan_matched_readers(core::TopicId id) const;
    /// The WAN participant's GUID prefix: how base-camp programs tell this gateway's status and writers apart.
    eprosima::fastrtps::rtps::GuidPrefix_t wan_guid_prefix() const;
    /// Base-camp participants the WAN participant knows now.
    std::size_t wan_participants() const;
    /// The WAN domain's discovery ports held quiet on the WAN interface's address (base::QuietDiscoveryPorts).
    const std::vector<std::uint16_t>& quiet_discovery_ports() const { return quiet_ports_.ports(); }
    std::optional<base::Duration> wan_writer_lifespan(core::TopicId id, std::uint16_t lane = 0) const;
    std::uint64_t wan_write_failures() const;
    /// The wire model the scheduler budgets with (without the statistics submessage in compact mode).
    const core::WireModel& wire_model() const { return config_.scheduler.wire; }
    /// The mean wire size of the WAN samples the base camp's receiver reports count: the robot's samples, or the
    /// bundles in compact mode.
    std::uint64_t mean_wan_sample_wire_bytes() const;
    /// Compact WAN mode: the bundles written so far; nullopt in standard mode.
    std::optional<CompactWan::Stats> wan_bundles() const;
    /// The WAN samples' RTPS messages and the datagrams that carried them.
    DatagramCoalescer::Counts wan_datagrams() const;
    /// The base camp's latest receiver report about this gateway; nullopt before one, or without
    /// GatewayConfig::receiver_reports.
    std::optional<ReceiverReportTotals> receiver_report() const;
    /// What the WAN participant sent beyond the scheduled writes, in Ethernet frame bytes: discovery,
    /// heartbeats, repairs, further copies (CoalescingTransport). Each byte is charged to the link budget.
    std::uint64_t unscheduled_wire_bytes() const;
    /// What became of the repairs reliable readers asked for (standard WAN mode): the scheduler's account, and the
    /// desk's that held them for it (nullopt in compact mode, where they go at once).
    core::RepairCounters repair_counters() const;
    std::optional<RepairDesk::Counts> repair_desk_counts() const;
    /// Repeated HEARTBEATs and ACKNACKs the WAN transport held back (RepeatThrottle), never sent nor charged.
    std::uint64_t suppressed_repeats() const;
    /// Announcements the WAN participant sent again to base camps that had not answered (IntroductionSchedule).
    std::uint64_t introductions() const;
    /// Samples handed to the on-robot log.
    std::uint64_t logged() const;
    /// The uplink's topics that a base-camp publisher was discovered of, with what became of their samples.
    std::vector<passthrough::UplinkCount> uplink_counts() const;

    /// The gateway's own processing time of every sample forwarded so far: from its arrival in the scheduler
    /// to the return of the WAN DataWriter's write (time queued for the link budget included).
    core::LatencyHistogram::Snapshot processing_latency() const;

    /// The status's row of every retired topic's counts together.
    static constexpr const char* RETIRED_TOPICS_ROW = "(retired topics)";

  private:
    struct WanCallbackLink;

    /// Samples of the robot's topics written to the WAN so far: what base-camp receiver reports count (the
    /// status is not among them); in compact mode the bundles, which the relay counts.
    std::uint64_t forwarded_robot_samples() const;
    /// Has the StatusPublisher look whether a status is due, and looks again after a status period.
    void publish_status_nts();  // the worker thread only
    /// The status's fields that the gateway knows beyond its rows (StatusPublisher::Sources::fill).
    void fill_status(idl::GatewayStatus& status, std::int32_t rows_readers) const;
    /// The status's rows: the topics bridged now, and the retired ones in one row.
    std::vector<TopicCount> status_rows() const;
    /// The backfill topic, its WAN writer, the sender reading the log and the reader of the camp's
    /// acknowledgements (GatewayConfig::backfill). Before the loop starts.
    void start_backfill();
    /// Tells the loop which topics a base-camp reader takes now, and looks again after REACHABILITY_POLL.
    void poll_reachability_nts();  // the worker thread only
    /// Counts traffic outside the schedule (what the WAN transport sent; commands received on a half-duplex link)
    /// and charges it to the loop (charge_link).
    void charge_unscheduled(std::uint64_t frame_bytes);
    /// Charges `frame_bytes` that crossed the link outside the schedule to the loop's budget: in the loop's own
    /// write, after it; otherwise through the worker.
    void charge_link(std::uint64_t frame_bytes);
    /// A base-camp writer discovered on the WAN: routed to the robot domain if its topic is on the uplink list.
    void remote_publisher_discovered(passthrough::DiscoveredPublisher&& pub);  // Fast DDS's discovery thread
    /// Routes a listed topic's base-camp publisher into the robot domain. The worker thread only.
    void route_uplink_nts(const passthrough::DiscoveredPublisher& pub, const std::string& robot_topic);
    /// The uplink's readers on the WAN participant and writers on the robot's, with --uplink.
    void make_uplink();
    void rebind_wan_nts(const std::string& address);
    /// Holds the rate at 0 from now until `remake` (which ends with remake_wan_nts) has run in the gateway's thread.
    void post_wan_remake(std::function<void()> remake);
    /// The WAN participant made anew on `address`, announcing to `peers`; in the gateway's own thread.
    void remake_wan_nts(const std::string& address, const std::vector<base::WanPeer>& peers);

    GatewayConfig config_;
    const base::Clock& clock_;
    TopicFilter filter_;
    /// The project's types and those of --idl; the bridges' key hashers point into it.
    const types::TypeLibrary types_;
    /// How the WAN participant's callbacks (unscheduled traffic, base-camp writers) reach this object while it lives.
    std::shared_ptr<WanCallbackLink> wan_callbacks_;
    passthrough::UplinkTopics uplink_topics_;
    /// What the camp's commands cost on the link: its datagrams as Fast DDS sends them (compact mode strips only
    /// this end's).
    core::WireModel camp_wire_;

    std::unique_ptr<log::RobotLog> log_;
    std::unique_ptr<ReceiverReportReader> reports_;  ///< before wan_: its reader's listener outlives it
    std::unique_ptr<GrantReader> grants_;            ///< before wan_, likewise; with --channel-grants
    /// With backfill: before the loop, which asks it for samples until it stops; the acknowledgements' listener
    /// before wan_, like the others.
    std::unique_ptr<BackfillSender> backfill_;
    std::unique_ptr<BackfillAckReader> backfill_acks_;
    std::unique_ptr<WanRouter> wan_;
    /// The WAN domain's discovery ports the WAN participant did not take, on a radio's address (see there).
    base::QuietDiscoveryPorts quiet_ports_;
    std::unique_ptr<CompactWan> compact_;  ///< after wan_: it holds WAN writers; compact WAN mode only
    std::unique_ptr<TopicTable> topics_;   ///< after wan_: its bridges hold WAN writers
    std::unique_ptr<GatewaySink> sink_;
    std::unique_ptr<core::ForwardingLoop> loop_;
    std::unique_ptr<RateControl> rate_;          ///< after loop_, which it sets the rate of
    std::unique_ptr<TopicLifecycle> lifecycle_;  ///< after loop_ and topics_, which it uses
    std::unique_ptr<passthrough::Discovery> discovery_;

    /// The worker thread: every *_nts function runs there, and DDS entities are made and deleted there only.
    base::EventLoop worker_;

    std::unique_ptr<RobotParticipant> robot_;
    std::unique_ptr<passthrough::Uplink> uplink_;           ///< with --uplink; closed by stop(), before robot_ goes
    std::atomic<std::uint64_t> unscheduled_wire_bytes_{0};  ///< the camp's commands (--duplex half) among them
    std::vector<base::WanPeer> peer_specs_;                 ///< --wan-peer as given, names resolved at start
    std::unique_ptr<PeerLookup> peer_lookup_;  ///< with --wan-peer host names: a change makes the participant anew
    std::atomic<std::uint64_t> wan_rebinds_{0};
    std::shared_ptr<WanWriter> status_writer_;   ///< standard WAN mode
    std::optional<core::TopicId> status_topic_;  ///< with a status period
    std::unique_ptr<StatusPublisher> status_;    ///< with a status period
    std::shared_ptr<WanWriter> backfill_writer_;
    std::optional<core::TopicId> backfill_topic_;  ///< with backfill
    mutable std::mutex sensor_mutex_;
    std::string sensor_description_;
    std::string sensor_detail_;
    double delivered_cap_bps_ = 0.0;                           ///< 0: the delivered-rate check does not cap
    std::atomic<std::uint64_t> pending_unscheduled_bytes_{0};  ///< reported, not yet charged to the loop
    std::atomic<bool> unscheduled_charge_posted_{false};
    /// loop_ once made, for Fast DDS's sending threads, which may report traffic while the constructor runs.
    std::atomic<core::ForwardingLoop*> charging_loop_{nullptr};
    std::mutex stop_mutex_;
    bool stopped_ = false;
};

}  // namespace tgw::dds
