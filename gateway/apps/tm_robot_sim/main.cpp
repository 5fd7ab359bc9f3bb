// tm-robot-sim: publishes a workload (the paper's four telemetry streams) like a robot would.
#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>

#include "base/cli_checks.hpp"
#include "base/config_error.hpp"
#include "base/fastdds_log_reporter.hpp"
#include "gateway/apps/tm_robot_sim/paper_publisher.hpp"
#include "gateway/apps/tm_robot_sim/pose_publisher.hpp"
#include "gateway/apps/tm_robot_sim/survey_route.hpp"
#include "gateway/apps/tm_robot_sim/workload_file.hpp"

namespace {

std::atomic<bool> g_stop{false};
constexpr double POSE_RATE_HZ = 5.0;

void on_signal(int) {
    g_stop.store(true);
}

}  // namespace

int main(int argc, char** argv) {
    tgw::base::report_fastdds_log_as("tm-robot-sim");
    CLI::App app{"tm-robot-sim: publishes the paper's telemetry workload (topics telemetry/A ... D) on a DDS domain"};
    app.set_version_flag("--version", std::string("tm-robot-sim ") + TGW_VERSION);
    int domain = 0;
    std::string workload = "paper";
    double rate_hz = 5.0;
    double duration_s = 60.0;
    double linger_s = 1.0;
    double wait_match_s = 0.0;
    tgw::base::PeerTransport transport;
    app.add_option("--domain", domain, "DDS domain id to publish on")
        ->check(tgw::base::number_in(0, 232, "a domain id from 0 to 232", "IN [0, 232]"));
    app.add_option("--workload", workload, "paper, or a file of lines 'TYPE TOPIC DATA_BYTES TTL_S [RATE_HZ]'");
    app.add_option("--rate-hz", rate_hz, "publications per second of each stream")->check(tgw::base::positive());
    app.add_option("--duration", duration_s, "seconds of publishing")->check(tgw::base::positive());
    app.add_option("--linger", linger_s, "seconds to wait at the end for readers to acknowledge")
        ->check(tgw::base::non_negative());
    app.add_option("--wait-match", wait_match_s,
                   "seconds to wait, before publishing, for every topic to have a subscriber (0: start at once)")
        ->check(tgw::base::non_negative());
    app.add_option("--peer", transport.peers,
                   "IPv4 address of the other end (repeatable): UDP unicast only, no multicast, no shared memory");
    app.add_option("--interface", transport.interface, "interface name or IPv4 address to bind every socket to");
    bool transient_local = false;
    app.add_flag("--transient-local", transient_local,
                 "writers keep their last samples (within the history and the TTL) for readers that join later, as "
                 "Fast DDS's default writer does (a camera driver left at its defaults); default: volatile");
    std::string pose_topic;
    app.add_option("--pose", pose_topic,
                   "also publish the robot's pose (tgw::idl::RobotPose, 5 Hz, TTL 1 s) on this topic as it drives a "
                   "60-s survey loop from the base camp (for tm-basecamp linkmap)");
    std::string field_trace;
    app.add_option("--field-trace", field_trace,
                   "write the link rate the loop's simulated radio field gives, one line a second for --duration, as "
                   "a trace for --sensor trace:FILE or the testbed's shaper, and exit");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }

    try {
        if (!field_trace.empty()) {
            std::ofstream out(field_trace);
            tgw::robot_sim::write_field_trace(out, duration_s);
            if (!out.flush())
                throw tgw::base::ConfigError("--field-trace: cannot write '" + field_trace + "'");
            return 0;
        }
        const auto streams = tgw::robot_sim::load_workload(workload, rate_hz);
        tgw::robot_sim::PaperPublisher publisher(domain, streams, transport,
                                                 transient_local ? tgw::robot_sim::WriterDurability::transient_local
                                                                 : tgw::robot_sim::WriterDurability::volatile_kind);
        std::signal(SIGINT, on_signal);
        std::signal(SIGTERM, on_signal);
        if (wait_match_s > 0) {
            if (const std::size_t unmatched = publisher.wait_for_readers(tgw::base::from_seconds(wait_match_s))) {
                std::cerr << "tm-robot-sim: " << unmatched << " topic(s) had no subscriber after --wait-match "
                          << wait_match_s << " s; publishing anyway\n";
            }
        }
        std::optional<tgw::robot_sim::PosePublisher> poses;
        if (!pose_topic.empty()) {
            poses.emplace(domain, pose_topic, POSE_RATE_HZ, std::chrono::seconds(1), transport);
            poses->start(g_stop);
        }
        const auto start = tgw::base::SteadyClock::now();
        const auto reports = publisher.run(tgw::base::from_seconds(duration_s), g_stop);
        const std::uint64_t poses_published = poses ? poses->published() : 0;
        poses.reset();
        const double elapsed = tgw::base::to_seconds(tgw::base::SteadyClock::now() - start);
        if (!g_stop.load())
            publisher.linger(tgw::base::from_seconds(linger_s));
        std::cout << "tm-robot-sim: domain " << domain << ", workload " << workload << "\n";
        tgw::robot_sim::print_reports(std::cout, reports, elapsed);
        if (!pose_topic.empty())
            std::cout << pose_topic << ": " << poses_published << " poses along the survey loop\n";
    } catch (const tgw::base::ConfigError& e) {
        std::cerr << "tm-robot-sim: " << e.what() << "\n";
        return 2;
    }
    return 0;
}
