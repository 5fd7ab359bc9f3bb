// tm-basecamp: the base camp's side of the link. record: every topic of a domain into SQLite; relay: every topic
// of the WAN domain into the camp's own domain; report: the paper's metrics per topic from a recording, and with
// the gateway's on-robot log where every missing sample went.
#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/config_error.hpp"
#include "base/config_file.hpp"
#include "base/fastdds_log_reporter.hpp"
#include "base/peer_transport.hpp"
#include "basecamp/analysis/grant_summary.hpp"
#include "basecamp/analysis/on_time_payload.hpp"
#include "basecamp/analysis/report.hpp"
#include "basecamp/capture/backfill_archive.hpp"
#include "basecamp/capture/recorder.hpp"
#include "basecamp/cli/echo_command.hpp"
#include "basecamp/cli/export_command.hpp"
#include "basecamp/cli/linkmap_command.hpp"
#include "basecamp/cli/merge_command.hpp"
#include "basecamp/cli/progress_line.hpp"
#include "basecamp/cli/relay_command.hpp"
#include "basecamp/cli/stats_command.hpp"
#include "basecamp/cli/status_command.hpp"
#include "basecamp/cli/subcommand.hpp"
#include "basecamp/recording/mcap_recording.hpp"
#include "basecamp/recording/sample_store.hpp"
#include "basecamp/sample/consumer_fan_out.hpp"
#include "basecamp/status/topic_robots.hpp"
#include "gateway/dds/qos_file.hpp"

namespace {

/// "4 topics, 1234 samples" for a progress line.
/// Splits "TOPIC=VALUE" at its last '='; topics may contain '='-free slashes and colons.
template <typename T>
std::map<std::string, T> parse_assignments(const std::vector<std::string>& items, const std::string& flag) {
    std::map<std::string, T> result;
    for (const std::string& item : items) {
        const auto eq = item.rfind('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == item.size())
            throw tgw::base::ConfigError(flag + ": expected TOPIC=VALUE, got '" + item + "'");
        try {
            std::size_t used = 0;
            const std::string value = item.substr(eq + 1);
            const double number = std::stod(value, &used);
            if (used != value.size() || number < 0)
                throw std::invalid_argument(value);
            result[item.substr(0, eq)] = static_cast<T>(number);
        } catch (const std::exception&) {
            throw tgw::base::ConfigError(flag + ": '" + item + "': the value is not a non-negative number");
        }
    }
    return result;
}

}  // namespace

int main(int argc, char** argv) {
    tgw::base::report_fastdds_log_as("tm-basecamp");
    CLI::App app{"tm-basecamp: records every topic of the WAN domain and reports on-time delivery per topic"};
    app.set_version_flag("--version", std::string("tm-basecamp ") + TGW_VERSION);
    app.require_subcommand(1);

    CLI::App* record = app.add_subcommand("record", "subscribe to every topic on a domain, one SQLite row per sample");
    int domain = 1;
    std::string out;
    double duration_s = 0.0;
    tgw::base::PeerTransport transport;
    record->add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0, 232));
    record->add_option(
        "--peer", transport.peers,
        "IPv4 address or host name of the robot (repeatable): UDP unicast only, no multicast, no shared memory");
    record->add_option("--interface", transport.interface, "interface name or IPv4 address to bind every socket to");
    tgw::basecamp::add_discovery_server_option(*record, transport);
    record->add_option("--out", out, "the SQLite file to write (WAL mode)");
    tgw::basecamp::McapOptions record_mcap;
    tgw::basecamp::add_mcap_options(*record, record_mcap, false);
    record->add_option("--duration", duration_s, "seconds to record; until SIGINT/SIGTERM without it")
        ->check(CLI::PositiveNumber);
    std::vector<std::string> record_topics;
    record->add_option("--topic", record_topics, "record only this topic (repeatable); every topic without it");
    std::string record_security;
    tgw::basecamp::add_security_option(*record, record_security);
    double report_period_s = 1.0;
    record
        ->add_option("--report-period", report_period_s,
                     "seconds between receiver reports to each gateway (tgw/receiver_report); 0: none")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();

    CLI::App* report = app.add_subcommand("report", "print received, on time and transmission time per topic");
    std::string in;
    std::vector<std::string> ttls;
    std::vector<std::string> offered;
    report->add_option("FILE", in, "a recording made by 'tm-basecamp record'")->required()->check(CLI::ExistingFile);
    report->add_option("--ttl", ttls, "TOPIC=SECONDS: the TTL to judge a topic by (default: the writer's Lifespan)");
    std::string qos_file;
    report->add_option("--qos", qos_file,
                       "Fast DDS XML: a data_writer profile named after a topic gives its TTL (after --ttl, before "
                       "the writer's Lifespan)");
    report->add_option("--offered", offered, "TOPIC=N: how many samples the robot published on a topic");
    std::string robot_log;
    std::vector<std::string> forwarded;
    long long since_ns = 0;
    report
        ->add_option("--robot-log", robot_log,
                     "the gateway's on-robot log (telemetry-gateway --log): account for every sample not received")
        ->check(CLI::ExistingFile);
    report->add_option("--forwarded", forwarded,
                       "TOPIC=N: how many samples the gateway wrote to the WAN (makes lost on the link exact)");
    CLI::Option* since =
        report->add_option("--since-ns", since_ns,
                           "ignore samples (recording and log) with a source time before this, ns since the epoch");
    double link_rate_bps = 0.0;
    CLI::Option* link_rate =
        report->add_option("--link-rate", link_rate_bps,
                           "bit/s: also print the on-time payload, the serialized bytes that arrived within their TTL "
                           "over the steady window, as a share of this rate");

    // Subcommands in files of their own.
    const std::vector<tgw::basecamp::Subcommand> subcommands = {
        tgw::basecamp::add_echo_command(app),    tgw::basecamp::add_export_command(app),
        tgw::basecamp::add_linkmap_command(app), tgw::basecamp::add_merge_command(app),
        tgw::basecamp::add_relay_command(app),   tgw::basecamp::add_stats_command(app),
        tgw::basecamp::add_status_command(app),
    };

    std::vector<tgw::base::ConfigFile*> config_files;
    for (const tgw::basecamp::Subcommand& subcommand : subcommands) {
        if (subcommand.config)
            config_files.push_back(subcommand.config.get());
    }
    if (const std::optional<int> exit_code = tgw::base::read_command_line(app, argc, argv, config_files))
        return *exit_code;

    try {
        for (const tgw::basecamp::Subcommand& subcommand : subcommands) {
            if (subcommand.command->parsed())
                return subcommand.run();
        }
        if (record->parsed()) {
            if (out.empty() && record_mcap.path.empty())
                throw tgw::base::ConfigError("--out or --mcap: say where to record");
            const auto security = tgw::basecamp::security_files(record_security);
            std::vector<tgw::basecamp::SampleConsumer*> files;
            std::unique_ptr<tgw::basecamp::SampleStore> store;
            std::unique_ptr<tgw::basecamp::BackfillArchive> backfill;
            if (!out.empty()) {
                store = std::make_unique<tgw::basecamp::SampleStore>(out, "--out");
                backfill = std::make_unique<tgw::basecamp::BackfillArchive>(*store);  // before any sample
                files.push_back(store.get());
            }
            std::unique_ptr<tgw::basecamp::McapRecording> mcap;
            if (!record_mcap.path.empty()) {
                mcap = std::make_unique<tgw::basecamp::McapRecording>(
                    record_mcap.path, "--mcap", tgw::types::TypeLibrary::project_and(record_mcap.idl_dirs, "--idl"),
                    tgw::basecamp::parse_mcap_compression(record_mcap.compression, "--compression"),
                    record_mcap.chunk_bytes);
                files.push_back(mcap.get());
            }
            tgw::basecamp::TopicRobots robots;  // for the summary: the robot of each topic, from the gateways' status
            files.push_back(&robots);
            tgw::basecamp::ConsumerFanOut recording(files);
            tgw::basecamp::Recorder recorder(domain, transport, recording, tgw::base::from_seconds(report_period_s),
                                             security);
            recorder.only(record_topics);
            if (backfill) {
                recorder.archive_backfill(*backfill);
            }
            tgw::basecamp::stop_on_signals();
            const auto duration = duration_s > 0 ? tgw::base::from_seconds(duration_s) : tgw::base::Duration::max() / 2;
            tgw::basecamp::run_with_progress(
                duration, tgw::basecamp::stop_requested(),
                [&](tgw::base::Duration slice) { recorder.run(slice, tgw::basecamp::stop_requested()); },
                [&] {
                    return "recording into " + (out.empty() ? record_mcap.path : out) + ": " +
                           tgw::basecamp::topics_and_samples(recorder.received());
                });
            recorder.stop();  // before the files close: a sample arriving now would reach one of them only
            std::cout << "tm-basecamp record: domain " << domain << " -> "
                      << (out.empty() ? "" : out + (record_mcap.path.empty() ? "" : " and ")) << record_mcap.path
                      << "\n";
            for (const auto& [topic, count] : recorder.received()) {
                const std::string robot = robots.robot_of(topic);
                std::cout << "  " << topic << ": " << count << " samples" << (robot.empty() ? "" : ", robot " + robot)
                          << "\n";
            }
            for (const auto& [gateway, totals] : recorder.delivery())
                std::cout << "  from participant " << tgw::basecamp::prefix_text(gateway) << ": "
                          << totals.received_samples << " received, " << totals.lost_samples
                          << " lost on the way (gaps in the writers' sequence numbers)\n";
            if (store) {
                store->flush();
                std::cout << "  rows written: " << store->rows_written() << ", write errors: " << store->write_errors()
                          << "\n";
                if (backfill->received() > 0) {
                    std::cout << "  backfill: " << backfill->received() << " samples from the robots' logs, "
                              << store->duplicate_backfill_rows() << " of them stored before\n";
                }
            }
            if (mcap) {
                const bool written = mcap->close();
                std::cout << "  MCAP messages written: " << mcap->messages() << (written ? "" : ", writing failed")
                          << "\n";
                if (!written)
                    return 1;
            }
        } else {
            tgw::basecamp::ReportOptions options;
            options.ttl_s = parse_assignments<double>(ttls, "--ttl");
            if (!qos_file.empty()) {
                tgw::dds::load_qos_file(qos_file);
                options.profile_ttl_s = [](const std::string& topic) -> std::optional<double> {
                    const auto lifespan = tgw::dds::writer_profile_lifespan(topic);
                    return lifespan ? std::optional<double>(tgw::base::to_seconds(*lifespan)) : std::nullopt;
                };
            }
            options.offered = parse_assignments<std::uint64_t>(offered, "--offered");
            options.forwarded = parse_assignments<std::uint64_t>(forwarded, "--forwarded");
            options.robot_log = robot_log;
            if (since->count() > 0)
                options.since_ns = since_ns;
            if (!options.forwarded.empty() && robot_log.empty())
                throw tgw::base::ConfigError("--forwarded: needs --robot-log");
            if (link_rate->count() > 0 && !(link_rate_bps > 0.0))
                throw tgw::base::ConfigError("--link-rate " + link_rate->as<std::string>() +
                                             ": expected bit/s above 0");
            const std::vector<tgw::basecamp::TopicReport> reports = tgw::basecamp::read_report(in, options);
            tgw::basecamp::print_report(std::cout, reports);
            if (const auto grants = tgw::basecamp::read_grant_summary(in))
                tgw::basecamp::print_grant_summary(std::cout, *grants);
            if (link_rate_bps > 0.0) {
                tgw::basecamp::print_on_time_payload(
                    std::cout, tgw::basecamp::read_on_time_payload(in, reports, options.since_ns, link_rate_bps),
                    link_rate_bps);
            }
        }
    } catch (const tgw::base::ConfigError& e) {
        // A flag's value from a file is told at its key there.
        std::cerr << "tm-basecamp: " << tgw::base::explain_config_error(e.what(), config_files) << "\n";
        return 2;
    }
    return 0;
}
