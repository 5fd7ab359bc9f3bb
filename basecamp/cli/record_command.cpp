#include "basecamp/cli/record_command.hpp"

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "base/config_error.hpp"
#include "base/time.hpp"
#include "basecamp/capture/backfill_archive.hpp"
#include "basecamp/capture/delivery_tally.hpp"
#include "basecamp/capture/recorder.hpp"
#include "basecamp/cli/progress_line.hpp"
#include "basecamp/recording/mcap_recording.hpp"
#include "basecamp/recording/mcap_writer.hpp"
#include "basecamp/recording/sample_store.hpp"
#include "basecamp/sample/consumer_fan_out.hpp"
#include "basecamp/status/topic_robots.hpp"
#include "types/type_library.hpp"

namespace tgw::basecamp {

namespace {

struct RecordOptions {
    int domain = 1;
    std::string out;
    double duration_s = 0.0;
    base::PeerTransport transport;
    McapOptions mcap;
    std::vector<std::string> topics;
    std::string security;
    double report_period_s = 1.0;
};

int run_record(const RecordOptions& options) {
    if (options.out.empty() && options.mcap.path.empty())
        throw base::ConfigError("--out or --mcap: say where to record");
    const auto security = security_files(options.security);
    std::vector<SampleConsumer*> files;
    std::unique_ptr<SampleStore> store;
    std::unique_ptr<BackfillArchive> backfill;
    if (!options.out.empty()) {
        store = std::make_unique<SampleStore>(options.out, "--out");
        backfill = std::make_unique<BackfillArchive>(*store);  // before any sample
        files.push_back(store.get());
    }
    std::unique_ptr<McapRecording> mcap;
    if (!options.mcap.path.empty()) {
        mcap = std::make_unique<McapRecording>(
            options.mcap.path, "--mcap", types::TypeLibrary::project_and(options.mcap.idl_dirs, "--idl"),
            parse_mcap_compression(options.mcap.compression, "--compression"), options.mcap.chunk_bytes);
        files.push_back(mcap.get());
    }
    TopicRobots robots;  // for the summary: the robot of each topic, from the gateways' status
    files.push_back(&robots);
    ConsumerFanOut recording(files);
    Recorder recorder(options.domain, options.transport, recording, base::from_seconds(options.report_period_s),
                      security);
    recorder.only(options.topics);
    if (backfill) {
        recorder.archive_backfill(*backfill);
    }
    stop_on_signals();
    const auto duration = options.duration_s > 0 ? base::from_seconds(options.duration_s) : base::Duration::max() / 2;
    run_with_progress(
        duration, stop_requested(), [&](base::Duration slice) { recorder.run(slice, stop_requested()); },
        [&] {
            return "recording into " + (options.out.empty() ? options.mcap.path : options.out) + ": " +
                   topics_and_samples(recorder.received());
        });
    recorder.stop();  // before the files close: a sample arriving now would reach one of them only
    std::cout << "tm-basecamp record: domain " << options.domain << " -> "
              << (options.out.empty() ? "" : options.out + (options.mcap.path.empty() ? "" : " and "))
              << options.mcap.path << "\n";
    for (const auto& [topic, count] : recorder.received()) {
        const std::string robot = robots.robot_of(topic);
        std::cout << "  " << topic << ": " << count << " samples" << (robot.empty() ? "" : ", robot " + robot) << "\n";
    }
    for (const auto& [gateway, totals] : recorder.delivery())
        std::cout << "  from participant " << prefix_text(gateway) << ": " << totals.received_samples << " received, "
                  << totals.lost_samples << " lost on the way (gaps in the writers' sequence numbers)\n";
    if (store) {
        store->flush();
        std::cout << "  rows written: " << store->rows_written() << ", write errors: " << store->write_errors() << "\n";
        if (backfill->received() > 0) {
            std::cout << "  backfill: " << backfill->received() << " samples from the robots' logs, "
                      << store->duplicate_backfill_rows() << " of them stored before\n";
        }
    }
    if (mcap) {
        const bool written = mcap->close();
        std::cout << "  MCAP messages written: " << mcap->messages() << (written ? "" : ", writing failed") << "\n";
        if (!written)
            return 1;
    }
    return 0;
}

}  // namespace

Subcommand add_record_command(CLI::App& app) {
    auto options = std::make_shared<RecordOptions>();
    CLI::App* command = app.add_subcommand("record", "subscribe to every topic on a domain, one SQLite row per sample");
    command->add_option("--domain", options->domain, "DDS domain id")->check(CLI::Range(0, 232));
    command->add_option(
        "--peer", options->transport.peers,
        "IPv4 address or host name of the robot (repeatable): UDP unicast only, no multicast, no shared memory");
    command->add_option("--interface", options->transport.interface,
                        "interface name or IPv4 address to bind every socket to");
    add_discovery_server_option(*command, options->transport);
    add_receive_buffer_option(*command, options->transport);
    command->add_option("--out", options->out, "the SQLite file to write (WAL mode)");
    add_mcap_options(*command, options->mcap, false);
    command->add_option("--duration", options->duration_s, "seconds to record; until SIGINT/SIGTERM without it")
        ->check(CLI::PositiveNumber);
    command->add_option("--topic", options->topics, "record only this topic (repeatable); every topic without it");
    add_security_option(*command, options->security);
    command
        ->add_option("--report-period", options->report_period_s,
                     "seconds between receiver reports to each gateway (tgw/receiver_report); 0: none")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    return {command, [options] { return run_record(*options); }};
}

}  // namespace tgw::basecamp
