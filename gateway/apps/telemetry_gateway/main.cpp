// telemetry-gateway: bridge every robot-domain topic into the WAN domain, most urgent first, within the link
// budget the rate sensor measures; log what is not sent.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "base/cli_checks.hpp"
#include "base/config_error.hpp"
#include "base/config_file.hpp"
#include "base/fastdds_log_reporter.hpp"
#include "base/robot_namespace.hpp"
#include "base/wan_address.hpp"
#include "core/policy_kind.hpp"
#include "gateway/apps/telemetry_gateway/topic_rules_file.hpp"
#include "gateway/dds/gateway.hpp"
#include "gateway/dds/rate_poller.hpp"
#include "gateway/dds/wan_router.hpp"
#include "gateway/log/default_log_path.hpp"
#include "sensor/delivered_rate_check.hpp"
#include "sensor/guarded_sensor.hpp"
#include "sensor/link_state_watch.hpp"
#include "sensor/rate_sensor.hpp"
#include "sensor/receiver_report_ledger.hpp"
#include "sensor/receiver_report_source.hpp"

namespace {

using tgw::base::ConfigError;

constexpr std::chrono::milliseconds SENSOR_POLL_INTERVAL{100};

void print_summary(const tgw::dds::Gateway& gateway, bool uplink_charged) {
    std::printf("%-32s %10s %10s %8s", "topic", "received", "forwarded", "queued");
    for (auto name : tgw::core::DROP_REASON_NAMES) {
        std::printf(" %9.*s", static_cast<int>(name.size()), name.data());
    }
    std::printf("  ttl\n");
    // Every topic the gateway bridged, retired ones too (their bridges went when their publishers did).
    const std::vector<tgw::dds::TopicCount> counts = gateway.topic_counts();
    for (const auto& topic : counts) {
        const tgw::core::TopicCounters& c = topic.counters;
        std::printf("%-32s %10llu %10llu %8llu", topic.name.c_str(), static_cast<unsigned long long>(c.received),
                    static_cast<unsigned long long>(c.forwarded), static_cast<unsigned long long>(c.queued));
        for (auto d : c.dropped) {
            std::printf(" %9llu", static_cast<unsigned long long>(d));
        }
        const auto source = tgw::passthrough::to_string(topic.ttl.source);
        std::printf("  %.3g s (%.*s%s)\n", tgw::base::to_seconds(topic.ttl.ttl), static_cast<int>(source.size()),
                    source.data(), topic.bridged ? "" : ", retired");
    }
    const auto latency = gateway.processing_latency();
    const auto us = [](tgw::base::Duration d) { return std::chrono::duration<double, std::micro>(d).count(); };
    std::printf(
        "processing per forwarded sample (arrival to WAN write, queueing included): %llu samples, median %.1f us, "
        "p99 %.1f us, max %.1f us\n",
        static_cast<unsigned long long>(latency.count), us(latency.median()), us(latency.percentile(0.99)),
        us(latency.max));
    std::printf("wire bytes per forwarded sample, as the budget charged them:");
    for (const auto& topic : counts) {
        const tgw::core::TopicCounters& c = topic.counters;
        if (c.forwarded > 0) {
            std::printf(" %s %.1f", topic.name.c_str(),
                        static_cast<double>(c.forwarded_wire_bytes) / static_cast<double>(c.forwarded));
        }
    }
    std::printf("\n");
    if (const auto bundles = gateway.wan_bundles(); bundles && bundles->bundles > 0) {
        const auto n = static_cast<double>(bundles->bundles);
        const double span_s = tgw::base::to_seconds(bundles->last - bundles->first);
        std::printf(
            "WAN bundles: %llu, %.2f entries (samples or chunks of one) each, %.0f bytes encoded and %.0f on the wire "
            "on average, one every "
            "%.0f ms\n",
            static_cast<unsigned long long>(bundles->bundles), static_cast<double>(bundles->entries) / n,
            static_cast<double>(bundles->encoded_bytes) / n, static_cast<double>(bundles->wire_bytes) / n,
            n > 1 ? 1000.0 * span_s / (n - 1) : 0.0);
    }
    const auto datagrams = gateway.wan_datagrams();
    std::printf(
        "WAN datagrams: %llu samples' messages in %llu datagrams (%.2f per datagram)",
        static_cast<unsigned long long>(datagrams.messages), static_cast<unsigned long long>(datagrams.datagrams),
        datagrams.datagrams == 0 ? 0.0
                                 : static_cast<double>(datagrams.messages) / static_cast<double>(datagrams.datagrams));
    if (datagrams.failed_datagrams > 0) {
        std::printf(", %llu failed after waiting", static_cast<unsigned long long>(datagrams.failed_datagrams));
    }
    if (datagrams.controls_held > 0) {
        std::printf("; %llu HEARTBEATs and GAPs alone held for the next message to their base camp, %llu rode with one",
                    static_cast<unsigned long long>(datagrams.controls_held),
                    static_cast<unsigned long long>(datagrams.controls_rode));
    }
    std::printf("\n");
    std::printf(
        "WAN traffic outside the schedule (discovery, heartbeats, repairs, copies to further readers, commands on a "
        "half-duplex link): %llu bytes, charged to the budget; %llu repeated heartbeats, acknacks and announcements "
        "held back; %llu announcements repeated to base camps that had not answered\n",
        static_cast<unsigned long long>(gateway.unscheduled_wire_bytes()),
        static_cast<unsigned long long>(gateway.suppressed_repeats()),
        static_cast<unsigned long long>(gateway.introductions()));
    if (const auto desk = gateway.repair_desk_counts(); desk && (desk->held > 0 || desk->gapped > 0)) {
        const tgw::core::RepairCounters repairs = gateway.repair_counters();
        std::printf(
            "repairs for reliable readers, in the schedule: %llu held, %llu sent (%llu bytes), %llu not sent as too "
            "late for their sample's deadline, %llu asked again while held, %llu discarded; %llu asked for past "
            "their deadline, answered with a GAP\n",
            static_cast<unsigned long long>(desk->held), static_cast<unsigned long long>(repairs.sent),
            static_cast<unsigned long long>(repairs.sent_wire_bytes), static_cast<unsigned long long>(repairs.late),
            static_cast<unsigned long long>(desk->repeats),
            static_cast<unsigned long long>(repairs.discarded + desk->send_failures),
            static_cast<unsigned long long>(desk->gapped));
    }
    if (const auto desk = gateway.repair_desk_counts(); desk && desk->announcements_held > 0) {
        const tgw::core::RepairCounters repairs = gateway.repair_counters();
        std::printf(
            "announcements of the WAN participant, in the schedule: %llu copies held, %llu sent (%llu bytes), %llu of "
            "them at the end of their wait, %llu left out as too long for the link then, %llu replaced by a newer "
            "one while held\n",
            static_cast<unsigned long long>(desk->announcements_held),
            static_cast<unsigned long long>(repairs.announcements_sent),
            static_cast<unsigned long long>(repairs.announcements_sent_wire_bytes),
            static_cast<unsigned long long>(repairs.announcements_late),
            static_cast<unsigned long long>(repairs.announcements_skipped),
            static_cast<unsigned long long>(desk->announcements_replaced));
    }
    if (const auto desk = gateway.repair_desk_counts(); desk && desk->writer_announcements_held > 0) {
        const tgw::core::RepairCounters repairs = gateway.repair_counters();
        std::printf(
            "announcements of the WAN writers, in their topics' urgency: %llu held, %llu sent (%llu bytes), "
            "%llu of them at the end of their wait\n",
            static_cast<unsigned long long>(desk->writer_announcements_held),
            static_cast<unsigned long long>(repairs.writer_announcements_sent),
            static_cast<unsigned long long>(repairs.writer_announcements_sent_wire_bytes),
            static_cast<unsigned long long>(repairs.writer_announcements_late));
    }
    if (const auto desk = gateway.repair_desk_counts(); desk && desk->continuations_held > 0) {
        const tgw::core::RepairCounters repairs = gateway.repair_counters();
        std::printf(
            "large samples paced, in the schedule: %llu fragments after their sample's first held, %llu sent (%llu "
            "bytes), %llu not sent as their sample could no longer arrive in time (or at exit): %llu samples cut "
            "short, logged as dropped\n",
            static_cast<unsigned long long>(desk->continuations_held),
            static_cast<unsigned long long>(repairs.continuations_sent),
            static_cast<unsigned long long>(repairs.continuations_sent_wire_bytes),
            static_cast<unsigned long long>(repairs.continuations_late),
            static_cast<unsigned long long>(repairs.samples_cut_short));
    }
    if (gateway.statuses_published() > 0) {
        const tgw::core::TopicCounters status = gateway.status_counters();
        std::printf(
            "status on tgw/status: %llu made, %llu forwarded, %llu past their TTL, %llu held back as "
            "too long for the link, %llu with no reader\n",
            static_cast<unsigned long long>(gateway.statuses_published()),
            static_cast<unsigned long long>(status.forwarded),
            static_cast<unsigned long long>(status.dropped_for(tgw::core::DropReason::expired) +
                                            status.dropped_for(tgw::core::DropReason::doomed)),
            static_cast<unsigned long long>(status.dropped_for(tgw::core::DropReason::oversize)),
            static_cast<unsigned long long>(status.dropped_for(tgw::core::DropReason::no_reader)));
    }
    if (const auto backfill = gateway.backfill_summary()) {
        const tgw::core::TopicCounters& sent = backfill->counters;
        std::printf(
            "backfill on tgw/backfill: %llu samples sent from the on-robot log (%llu bytes on the link, %.0f each), "
            "%llu rows acknowledged by the base camp; %zu rows not yet in its archive (%llu bytes)\n",
            static_cast<unsigned long long>(backfill->counts.sent),
            static_cast<unsigned long long>(sent.forwarded_wire_bytes),
            sent.forwarded > 0 ? static_cast<double>(sent.forwarded_wire_bytes) / static_cast<double>(sent.forwarded)
                               : 0.0,
            static_cast<unsigned long long>(backfill->counts.acknowledged), backfill->backlog.rows,
            static_cast<unsigned long long>(backfill->backlog.bytes));
    }
    if (const auto report = gateway.receiver_report()) {
        std::printf(
            "base camp's last receiver report (of %llu): %llu samples received, %llu lost on the way, %llu in "
            "flight\n",
            static_cast<unsigned long long>(report->reports), static_cast<unsigned long long>(report->received_samples),
            static_cast<unsigned long long>(report->lost_samples),
            static_cast<unsigned long long>(report->in_flight_samples));
    }
    for (const tgw::passthrough::UplinkCount& up : gateway.uplink_counts()) {
        // The gateway always resolves a TTL (--default-ttl at last).
        const tgw::passthrough::ResolvedTtl ttl = up.ttl.value_or(tgw::passthrough::ResolvedTtl{});
        const auto source = tgw::passthrough::to_string(ttl.source);
        std::printf(
            "uplink %s -> %s: %llu received, %llu delivered, %llu expired before they came (never delivered), "
            "%llu failed, %llu written while no robot reader listened; TTL %.3g s (%.*s); %llu bytes on the link%s\n",
            up.from_topic.c_str(), up.to_topic.c_str(), static_cast<unsigned long long>(up.received),
            static_cast<unsigned long long>(up.delivered), static_cast<unsigned long long>(up.expired),
            static_cast<unsigned long long>(up.failed), static_cast<unsigned long long>(up.no_reader),
            tgw::base::to_seconds(ttl.ttl), static_cast<int>(source.size()), source.data(),
            static_cast<unsigned long long>(up.wire_bytes),
            uplink_charged ? ", charged to the budget (--duplex half)" : " (--duplex full: not charged)");
    }
}

/// Blocks until SIGINT or SIGTERM, or `duration_s` (when positive) has passed.
void wait_for_end(const sigset_t& signals, double duration_s) {
    if (duration_s <= 0) {
        int sig = 0;
        sigwait(&signals, &sig);
        return;
    }
    const auto end = std::chrono::steady_clock::now() + tgw::base::from_seconds(duration_s);
    while (true) {
        const auto left = end - std::chrono::steady_clock::now();
        if (left <= std::chrono::nanoseconds::zero()) {
            return;
        }
        const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
        timespec ts{static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
        if (sigtimedwait(&signals, nullptr, &ts) > 0) {
            return;
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    tgw::base::report_fastdds_log_as("telemetry-gateway");
    CLI::App app{"telemetry-gateway: bridge robot-domain DDS topics to the WAN domain within the link's rate"};
    app.set_version_flag("--version", std::string("telemetry-gateway ") + TGW_VERSION);
    tgw::dds::GatewayConfig config;
    std::string sensor_spec = "fixed:50000";
    std::string policy_name = "ttl";
    double duration_s = 0.0;
    double default_ttl_s = 5.0;
    // The scheduler's budget fraction is the margin; the rate follows a new reading within one poll.
    tgw::sensor::GuardConfig guard;
    guard.margin = 0.0;
    guard.smoothing = 1.0;
    double hold_s = tgw::base::to_seconds(guard.hold);
    bool arrival_clock = false;
    bool delivered_check = false;
    std::string delivered_interface;
    app.add_option("--robot-domain", config.robot_domain, "DDS domain of the robot's processes")->capture_default_str();
    app.add_option("--wan-domain", config.wan_domain, "DDS domain towards the base camp")->capture_default_str();
    app.add_option("--wan-peer", config.wan_peers,
                   "base-camp host, IPv4 or host name [:PORT], required without --wan-discovery-server: the gateway "
                   "announces itself to its peers only; without a port, to the ports of its first "
                   "--wan-peer-participants participants; a name is looked up every 5 s (one that resolves late, "
                   "or changes, makes the WAN participant anew); repeatable");
    app.add_option("--wan-discovery-server", config.wan_discovery_server,
                   "ADDR:PORT of a Fast DDS Discovery Server on the WAN (fastdds discovery -i 0 -l ADDR -p PORT): "
                   "discovery through it instead of announcements to --wan-peer");
    app.add_option("--wan-peer-participants", config.wan_peer_participants,
                   "base-camp programs (DDS participants) per --wan-peer host that find the gateway without "
                   "announcing themselves to the robot; each costs an announcement on the link")
        ->capture_default_str();
    app.add_option("--wan-interface", config.wan_interface,
                   "interface name or IPv4 address to bind the WAN to; a name is followed: while it is down or has no "
                   "IPv4 address nothing is sent, and when its address changes the WAN participant is made anew");
    app.add_option("--wan-port", config.wan_port, "own WAN metatraffic port (default: Fast DDS's well-known port)");
    std::size_t max_datagram = config.scheduler.wire.max_datagram_bytes;
    CLI::Option* max_datagram_option =
        app.add_option("--wan-max-datagram", max_datagram,
                       "largest UDP payload on the WAN, bytes; larger samples are fragmented. The default fits one "
                       "Ethernet frame (with --wan-security: 8192, the least its handshake needs); up to 65500 on a "
                       "fast link saves the fragments' headers and syscalls")
            ->capture_default_str();
    auto coalesce_us = static_cast<std::int64_t>(config.wan_coalesce_window.count());
    app.add_option("--wan-coalesce-us", coalesce_us,
                   "a WAN sample that follows the previous datagram within this many microseconds waits as long "
                   "to share a datagram with the next ones; a sample that comes alone goes at once; 0: never")
        ->capture_default_str();
    std::string wan_mode = "standard";
    app.add_option("--wan-mode", wan_mode,
                   "standard: a DDS sample per sample, any DDS reader at the base camp; compact: what the scheduler "
                   "releases together leaves as one bundle on tgw/compact/bundles, which tm-basecamp relay unpacks")
        ->check(CLI::IsMember({"standard", "compact"}))
        ->capture_default_str();
    app.add_flag("--wan-compress", config.wan_compress,
                 "compact mode: zstd-compress a bundle's entries where that makes it smaller");
    app.add_option("--wan-security", config.wan_security,
                   "DDS Security on the WAN participant (authentication, encryption, access control) with this "
                   "identity directory, made by scripts/make-certs (DIR/gateway); checked at start. The robot "
                   "domain stays plain");
    app.add_option("--wan-heartbeat-bytes", config.wan_heartbeat_bytes,
                   "a reliable WAN writer piggy-backs a HEARTBEAT (and draws an ACKNACK from each reader) once "
                   "per this many bytes it sends; 0: with every sample, so a lost one is repaired a sample later")
        ->capture_default_str();
    double status_period_s = 1.0;
    app.add_option("--status-period", status_period_s,
                   "seconds between the gateway's status samples on tgw/status (less often where that would take "
                   "more than 2 % of the sensed rate; scheduled like a sample with a TTL of 1 s); 0: none")
        ->check(tgw::base::non_negative())
        ->capture_default_str();
    app.add_option("--robot-interface", config.robot.interfaces,
                   "IPv4 address or interface the robot domain's UDP uses; repeatable")
        ->capture_default_str();
    app.add_flag("--robot-shm", config.robot.shm,
                 "Fast DDS shared memory too on the robot domain, for processes that use nothing else; they must "
                 "run as the gateway's user (others then cannot reach it), and a process with both transports "
                 "sends every sample both ways");
    app.add_option("--robot-receive-buffer", config.robot.receive_buffer_bytes,
                   "bytes of UDP receive buffer for the robot domain: room for bursts (capped by "
                   "net.core.rmem_max)")
        ->capture_default_str();
    app.add_option("--sensor", sensor_spec, "link rate sensor: fixed:BPS, trace:FILE, ...")->capture_default_str();
    app.add_option("--sensor-hold", hold_s, "seconds a failed sensor's last good rate still stands")
        ->check(tgw::base::non_negative())
        ->capture_default_str();
    app.add_option("--sensor-floor", guard.floor_bps, "bit/s used once the hold is over, or before any good reading")
        ->check(tgw::base::positive())
        ->capture_default_str();
    app.add_option("--sensor-smoothing", guard.smoothing,
                   "weight of a rising reading in the sensor's average, (0, 1]; 1 follows at once")
        ->capture_default_str();
    app.add_option("--sensor-margin", guard.margin,
                   "fraction taken off the sensor's rate, [0, 1); the budget fraction is a margin already")
        ->capture_default_str();
    auto* check = app.add_flag("--delivered-check", delivered_check,
                               "cap the budget below the sensor's rate while the WAN interface's qdisc drops or "
                               "queues (needs --wan-interface or --delivered-interface)");
    app.add_flag(
        "--receiver-reports", config.receiver_reports,
        "cap the budget also while the base camp's receiver (tm-basecamp record) reports samples queued or lost on the "
        "way; alone, without --delivered-check, the reports are the check's only counters");
    app.add_option("--delivered-interface", delivered_interface,
                   "interface whose counters the delivered-rate check reads (default: --wan-interface)")
        ->needs(check);
    app.add_option("--policy", policy_name, "ttl, edf, paper or fifo")->capture_default_str();
    CLI::Option* budget_fraction =
        app.add_option("--budget-fraction", config.scheduler.budget_fraction,
                       "share of the sensed rate the scheduler spends; the rest absorbs discovery traffic (default: "
                       "0.95, in --wan-mode compact 0.99)")
            ->check(tgw::base::number_in(0.01, 1.0, "a fraction from 0.01 to 1", "IN [0.01, 1]"));
    double queue_mib = static_cast<double>(config.scheduler.memory_cap_bytes) / (1 << 20);
    app.add_option("--queue-memory", queue_mib,
                   "MiB the queue may hold (payloads and bookkeeping); past it the least urgent sample goes to the log")
        ->check(tgw::base::positive())
        ->capture_default_str();
    app.add_option("--qos", config.qos_file, "Fast DDS XML profiles (data_writer profiles named after topics)");
    app.add_option("--idl", config.idl_dirs,
                   "directory of IDL files (repeatable): a keyed type declared there gets its key hash computed "
                   "from the payload when its publisher sends none (Cyclone DDS's default), so the gateway's "
                   "history keeps each instance");
    CLI::Option* log_option = app.add_option(
        "--log", config.log_file,
        "on-robot SQLite log: every sample not sent, with its payload and why, and a row per sample sent (no "
        "payload); default: robot-log.db in $XDG_STATE_HOME/telemetry-gateway, else ~/.local/state/telemetry-gateway");
    bool no_log = false;
    app.add_flag("--no-log", no_log, "keep no on-robot log: what is not sent is only counted")->excludes(log_option);
    double log_max_mib = 1024;
    app.add_option("--log-max-mib", log_max_mib,
                   "MiB the on-robot log may take; past it the oldest rows make room: first those the camp has "
                   "acknowledged (backfill), then those of samples sent, then the rest")
        ->check(tgw::base::positive())
        ->capture_default_str();
    // Backfill is on wherever there is an on-robot log: its rows cross to a camp that stores them (relay --out,
    // record --out) in capacity no live sample wants (docs/design/backfill.md).
    bool no_backfill = false;
    CLI::Option* no_backfill_option = app.add_flag(
        "--no-backfill", no_backfill,
        "keep the on-robot log's rows on the robot: by default they cross to the base camp in capacity no live "
        "sample wants, until the camp acknowledges them (tm-basecamp relay --out, record --out)");
    app.add_option("--backfill-max-bps", config.backfill_max_bps,
                   "the most bit/s backfill may take (a link billed per byte); default: whatever the budget leaves")
        ->check(tgw::base::positive())
        ->excludes(no_backfill_option);
    app.add_option("--robot-name", config.robot_name,
                   "the robot's name in a fleet: its topics appear on the WAN as rt/NAME/... (ROS 2 topics, and rq/, "
                   "rr/ services) or NAME/... (any other); letters, digits and '_'");
    app.add_option("--allow", config.allow, "bridge only topics matching this glob; repeatable");
    app.add_option("--uplink", config.uplink,
                   "a topic the base camp may publish into the robot domain (commands: rt/cmd_vel, published at the "
                   "base camp as rt/NAME/cmd_vel with --robot-name NAME), delivered only within its TTL; repeatable, "
                   "nothing else flows from the WAN to the robot");
    app.add_flag("--channel-grants", config.channel_grants,
                 "a fleet's shared channel: budget for the lower of the sensor's rate and this gateway's share, "
                 "which the base camp grants on tgw/grant (tm-basecamp relay --channel-rate) from the statuses; the "
                 "status goes first and also when the demand moves; without a grant of its own, the newcomers' share "
                 "(or a tenth of the sensor's rate for the first 30 s), and the sensor's rate once no grant is valid");
    std::string duplex = "half";
    app.add_option("--duplex", duplex,
                   "half: the radio carries both directions on one channel (Wi-Fi, most telemetry radios), so the "
                   "--uplink commands' bytes are charged to the budget; full: each direction has its own (a shaped "
                   "testbed link), and they are only counted")
        ->check(CLI::IsMember({"half", "full"}))
        ->capture_default_str();
    app.add_option("--deny", config.deny, "never bridge topics matching this glob; repeatable, wins over --allow");
    app.add_option("--duration", duration_s, "seconds to run (default: until SIGINT/SIGTERM)")
        ->check(tgw::base::positive());
    app.add_option("--default-ttl", default_ttl_s, "TTL in seconds of topics with no profile or Lifespan")
        ->check(tgw::base::positive())
        ->capture_default_str();
    auto* trust = app.add_flag("--trust-source-clock", "deadlines from the publisher's source timestamp (default)");
    app.add_flag("--arrival-clock", arrival_clock, "deadlines from the arrival at the gateway")->excludes(trust);
    tgw::base::ConfigFile config_file(app, {"topics"});
    const auto read_topic_rules = [&] {
        config.topic_rules = tgw::gateway_app::read_topic_rules(config_file.section("topics"), config_file.file());
        return tgw::gateway_app::topic_rules_yaml(config.topic_rules);
    };
    try {
        if (const std::optional<int> exit_code =
                tgw::base::read_command_line(app, argc, argv, {&config_file}, read_topic_rules)) {
            return *exit_code;
        }
        read_topic_rules();
    } catch (const ConfigError& e) {
        std::cerr << "telemetry-gateway: " << e.what() << '\n';
        return 2;
    }
    for (const tgw::dds::TopicRule& rule : config.topic_rules.rules()) {
        if (rule.uplink && std::find(config.uplink.begin(), config.uplink.end(), rule.match) == config.uplink.end())
            config.uplink.push_back(rule.match);
    }

    // Signals are taken by sigwait in this thread only; every thread created from here on inherits the mask.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    try {
        const auto policy = tgw::core::parse_policy(policy_name);
        if (!policy) {
            throw ConfigError("--policy '" + policy_name + "': expected ttl, edf, paper or fifo");
        }
        config.scheduler.policy = *policy;
        config.scheduler.trust_source_clock = !arrival_clock;
        config.default_ttl = tgw::base::from_seconds(default_ttl_s);
        config.scheduler.memory_cap_bytes = static_cast<std::size_t>(queue_mib * (1 << 20));
        if (!config.wan_security.empty() && max_datagram_option->count() == 0) {
            max_datagram = tgw::dds::SECURE_MIN_DATAGRAM_BYTES;
        }
        config.scheduler.wire = tgw::core::WireModel::for_max_datagram(max_datagram);
        config.wan_coalesce_window = std::chrono::microseconds(coalesce_us);
        config.status_period = tgw::base::from_seconds(status_period_s);
        config.compact_wan = wan_mode == "compact";
        config.uplink_shares_link = duplex == "half";
        if (!no_log) {
            if (config.log_file.empty()) {
                config.log_file = tgw::log::default_log_path(std::getenv("XDG_STATE_HOME"), std::getenv("HOME"));
                const std::filesystem::path dir = std::filesystem::path(config.log_file).parent_path();
                std::error_code error;
                if (!dir.empty() && (std::filesystem::create_directories(dir, error), error)) {
                    throw ConfigError("--log: cannot create " + dir.string() + " for the default on-robot log: " +
                                      error.message() + " (give --log FILE, or --no-log)");
                }
            }
            config.log_max_bytes = static_cast<std::uint64_t>(log_max_mib * (1 << 20));
            config.backfill = !no_backfill;
        }
        if (config.compact_wan && budget_fraction->count() == 0) {
            config.scheduler.budget_fraction = tgw::core::SchedulerConfig::COMPACT_BUDGET_FRACTION;
        }

        guard.hold = tgw::base::from_seconds(hold_s);
        if (!(guard.smoothing > 0.0 && guard.smoothing <= 1.0)) {
            throw ConfigError("--sensor-smoothing " + std::to_string(guard.smoothing) + ": must be in (0, 1]");
        }
        if (!(guard.margin >= 0.0 && guard.margin < 1.0)) {
            throw ConfigError("--sensor-margin " + std::to_string(guard.margin) + ": must be in [0, 1)");
        }
        tgw::base::SystemClock clock;
        const tgw::sensor::SensorLog sensor_log = [](tgw::sensor::SensorLogLevel, const std::string& message) {
            std::cerr << "telemetry-gateway: " << message << '\n';
        };
        std::unique_ptr<tgw::sensor::RateSensor> sensor;
        try {
            sensor = tgw::sensor::make_guarded_sensor(sensor_spec, guard, clock, sensor_log);
        } catch (const ConfigError& e) {
            throw ConfigError(std::string("--") + e.what());  // the message starts "sensor SPEC: "
        }
        if (delivered_check && delivered_interface.empty()) {
            if (config.wan_interface.empty()) {
                throw ConfigError(
                    "--delivered-check: name the interface with --wan-interface or --delivered-interface");
            }
            delivered_interface = tgw::base::resolve_interface_name(config.wan_interface);
        }
        // Checked before the participants start, so a wrong interface is a start-up error.
        std::optional<tgw::sensor::DeliveredRateSources> delivered_sources;
        if (delivered_check) {
            try {
                delivered_sources = tgw::sensor::kernel_sources(delivered_interface, {});
            } catch (const ConfigError& e) {
                throw ConfigError(std::string("--delivered-check: ") + e.what());
            }
        }
        const tgw::sensor::RateReading first = sensor->read();
        if (first.ok) {
            config.scheduler.initial_rate_bps = first.rate_bps;
        }

        tgw::dds::Gateway gateway(config, clock);
        if (config.receiver_reports) {
            if (!delivered_sources) {
                delivered_sources.emplace();
            }
            const tgw::core::WireModel wire = gateway.wire_model();
            delivered_sources->kernel = tgw::sensor::with_receiver_reports(
                std::move(delivered_sources->kernel), [&gateway, wire]() -> std::optional<tgw::sensor::ReceiverCounts> {
                    const auto report = gateway.receiver_report();
                    if (!report) {
                        return std::nullopt;
                    }
                    return tgw::sensor::receiver_counts(*report, wire.per_datagram_bytes + wire.per_sample_bytes,
                                                        gateway.mean_wan_sample_wire_bytes());
                });
        }
        if (delivered_sources) {
            delivered_sources->sent_bytes = [&gateway] { return gateway.total_counters().forwarded_wire_bytes; };
            sensor = std::make_unique<tgw::sensor::DeliveredRateCheck>(std::move(sensor), std::move(*delivered_sources),
                                                                       tgw::sensor::DeliveredRateConfig{}, clock,
                                                                       sensor_log);
        }
        gateway.set_sensor_description(sensor->describe());
        tgw::dds::RatePoller poller(
            *sensor, [&gateway](const tgw::sensor::RateReading& reading) { gateway.apply_reading(reading); },
            SENSOR_POLL_INTERVAL);
        poller.start();
        std::cerr << "telemetry-gateway: robot domain " << config.robot_domain << " -> WAN domain " << config.wan_domain
                  << " (" << wan_mode << "), policy " << policy_name << ", sensor " << sensor->describe()
                  << ", on-robot log " << (config.log_file.empty() ? std::string("none (--no-log)") : config.log_file)
                  << '\n';
        if (!config.robot_name.empty()) {
            std::cerr << "telemetry-gateway: robot " << config.robot_name << ": its topics are "
                      << tgw::base::namespaced_topic(config.robot_name, "rt/TOPIC") << " and "
                      << tgw::base::namespaced_topic(config.robot_name, "TOPIC")
                      << " on the WAN and in the on-robot log; below, by their robot names\n";
        }
        if (const auto& quiet = gateway.quiet_discovery_ports(); !quiet.empty()) {
            std::cerr << "telemetry-gateway: WAN discovery ports " << quiet.front() << " to " << quiet.back()
                      << " held (" << quiet.size() << ", not this gateway's): a base camp's announcements to them "
                      << "draw no ICMP over the radio\n";
        }

        // A radio that is down (or not up yet) is a rate of 0, not a dead program: the WAN participant works once
        // it is up.
        std::unique_ptr<tgw::sensor::LinkStateWatch> link_watch;
        if (!config.wan_interface.empty()) {
            const std::string wan_name = tgw::base::resolve_interface_name(config.wan_interface);
            link_watch = std::make_unique<tgw::sensor::LinkStateWatch>(
                wan_name, [&gateway, wan_name](const tgw::sensor::LinkState& state) {
                    // An address that went (a new DHCP lease, a mesh radio's), or the first one (an interface with
                    // none at start): the participant announces one that nobody can reach. First, so that the
                    // rate stays 0 until the participant is bound to the new one.
                    const std::string bound = gateway.wan_interface_address();
                    if (!state.addresses.empty() && !bound.empty() &&
                        std::find(state.addresses.begin(), state.addresses.end(), bound) == state.addresses.end()) {
                        std::cerr << "telemetry-gateway: WAN interface " << wan_name << " has "
                                  << state.addresses.front() << " now, not " << bound
                                  << ": the WAN participant is made anew on it\n";
                        gateway.rebind_wan(state.addresses.front());
                    }
                    if (state.usable() == gateway.wan_link_up()) {
                        return;
                    }
                    gateway.set_wan_link_up(state.usable());
                    if (state.usable()) {
                        std::cerr << "telemetry-gateway: WAN interface " << wan_name << " up: sending again\n";
                    } else {
                        std::cerr << "telemetry-gateway: WAN interface " << wan_name << " "
                                  << tgw::sensor::describe(state) << ": nothing is sent until it is up"
                                  << (state.up ? " with one" : "")
                                  << "; samples wait for it, or go to the on-robot log as their TTL passes\n";
                    }
                });
            link_watch->start();
        }

        wait_for_end(signals, duration_s);

        if (link_watch) {
            link_watch->stop();
        }
        poller.stop();
        gateway.stop();
        print_summary(gateway, config.uplink_shares_link);
    } catch (const ConfigError& e) {
        // A flag's value from the file is told at its key there.
        std::cerr << "telemetry-gateway: " << config_file.explain(e.what()) << '\n';
        return 2;
    }
    return 0;
}
