// publisher_churn_bench: the gateway's resident memory while robot topics come and go (issue 20, publisher churn).
//
// Method: telemetry-gateway runs as its own process (robot and WAN domains of this process, the WAN on loopback, a
// fixed rate, TTL --ttl-s, its on-robot log in a temporary file); this program is the robot. A cycle: --topics
// writers appear, one per topic (churn/tN, the same names each cycle unless --fresh-names), each waits for the
// gateway's reader, publishes --samples PaperMessages, and all are deleted; the cycle ends when the robot domain has
// no reader of the gateway's on those topics left (every bridge retired) and a second has passed. No base camp
// reads them, so each sample is held to its deadline and logged as no_reader. VmRSS of the gateway's process (from
// /proc) is read after a first cycle (the baseline: Fast DDS allocates its pools on first use), then in each cycle
// once every topic is bridged and once every topic is gone. At the end the gateway is stopped (SIGTERM) and its exit
// summary is read: every topic must be there, retired, with received = --samples x cycles = forwarded + queued +
// dropped. Exit 0 when the last "gone" figure is within --max-growth-percent of the baseline and every count
// holds; 1 otherwise.
#include <signal.h>

#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "PaperWorkloadPubSubTypes.h"
#include "core/drop_reason.hpp"
#include "test/bench/bench_support.hpp"
#include "test/integration/child_process.hpp"

namespace {

using namespace std::chrono_literals;
using tgw::test::ChildProcess;
using tgw::test::MatchCounter;
using tgw::test::TestParticipant;
namespace fdds = eprosima::fastdds::dds;

struct Options {
    std::string gateway = TGW_GATEWAY_PROGRAM;
    int topics = 100;
    int cycles = 4;
    int samples = 3;
    int ttl_s = 1;
    bool fresh_names = false;
    bool no_log = false;
    double max_growth_percent = 10.0;
    int timeout_s = 30;
    std::vector<std::string> gateway_args;  ///< more flags for the gateway (--wan-mode compact, ...)
};

/// Counts the gateway's readers of the churned topics on the robot domain, as discovery reports them.
class GatewayReaders final : public fdds::DomainParticipantListener {
  public:
    explicit GatewayReaders(std::string prefix) : prefix_(std::move(prefix)) {}

    void on_subscriber_discovery(fdds::DomainParticipant* /*participant*/,
                                 eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) override {
        using Status = eprosima::fastrtps::rtps::ReaderDiscoveryInfo;
        if (info.info.topicName().to_string().rfind(prefix_, 0) != 0) {
            return;
        }
        std::lock_guard<std::mutex> lock(mutex_);
        if (info.status == Status::DISCOVERED_READER) {
            readers_.insert(info.info.guid());
        } else if (info.status == Status::REMOVED_READER) {
            readers_.erase(info.info.guid());
        }
    }

    std::size_t count() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return readers_.size();
    }

  private:
    const std::string prefix_;
    mutable std::mutex mutex_;
    std::set<eprosima::fastrtps::rtps::GUID_t> readers_;
};

bool wait_until(const std::function<bool()>& condition, std::chrono::seconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!condition()) {
        if (std::chrono::steady_clock::now() >= end) {
            return false;
        }
        std::this_thread::sleep_for(20ms);
    }
    return true;
}

struct CycleFigures {
    long bridged_kb = 0;
    long gone_kb = 0;
    double seconds = 0;
};

class Churn {
  public:
    Churn(const Options& options, TestParticipant& robot, GatewayReaders& readers, std::string prefix)
        : options_(options), robot_(robot), readers_(readers), prefix_(std::move(prefix)) {}

    /// One cycle; false (after saying why) when the gateway did not follow within the timeout.
    bool run(int cycle, pid_t gateway, CycleFigures& figures) {
        const auto start = std::chrono::steady_clock::now();
        const std::chrono::seconds timeout(options_.timeout_s);
        std::vector<fdds::DataWriter*> writers;
        std::vector<std::unique_ptr<MatchCounter>> matches;
        fdds::DataWriterQos qos = robot_.default_writer_qos();
        qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
        qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
        qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        qos.history().depth = 10;
        for (int i = 0; i < options_.topics; ++i) {
            const std::string topic =
                prefix_ + (options_.fresh_names ? "c" + std::to_string(cycle) + "/" : "") + "t" + std::to_string(i);
            topics_.insert(topic);
            matches.push_back(std::make_unique<MatchCounter>());
            writers.push_back(robot_.make_writer(topic, fdds::TypeSupport(new tgw::idl::PaperMessagePubSubType()), qos,
                                                 matches.back().get()));
            if (writers.back() == nullptr) {
                std::fprintf(stderr, "publisher_churn_bench: cannot create the writer of %s\n", topic.c_str());
                return false;
            }
        }
        for (int i = 0; i < options_.topics; ++i) {
            if (!wait_until([&] { return matches[i]->matched.load() > 0; }, timeout)) {
                std::fprintf(stderr, "publisher_churn_bench: cycle %d: topic %d was never bridged\n", cycle, i);
                return false;
            }
            for (int n = 0; n < options_.samples; ++n) {
                tgw::idl::PaperMessage m;
                m.generated_ns(static_cast<std::uint64_t>(n));
                m.data(std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(n)));
                writers[i]->write(&m);
            }
        }
        // Reliable writers: wait until each has its samples acknowledged by the gateway's reader.
        for (fdds::DataWriter* writer : writers) {
            writer->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(options_.timeout_s, 0));
        }
        figures.bridged_kb = tgw::bench::rss_kb(std::to_string(gateway));
        for (fdds::DataWriter* writer : writers) {
            const_cast<fdds::Publisher*>(writer->get_publisher())->delete_datawriter(writer);
        }
        if (!wait_until([&] { return readers_.count() == 0; }, timeout)) {
            std::fprintf(stderr, "publisher_churn_bench: cycle %d: %zu readers of the gateway left\n", cycle,
                         readers_.count());
            return false;
        }
        std::this_thread::sleep_for(1s);  // the topics retired with their last lane; their entities are gone
        figures.gone_kb = tgw::bench::rss_kb(std::to_string(gateway));
        figures.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return true;
    }

    const std::set<std::string>& topics() const { return topics_; }

  private:
    const Options& options_;
    TestParticipant& robot_;
    GatewayReaders& readers_;
    const std::string prefix_;
    std::set<std::string> topics_;
};

/// Reads the exit summary's topic rows of `prefix` from the gateway's output: name -> the numbers after it.
std::map<std::string, std::vector<unsigned long long>> summary_rows(ChildProcess& gateway, const std::string& prefix) {
    std::map<std::string, std::vector<unsigned long long>> rows;
    const auto deadline = std::chrono::steady_clock::now() + 30s;
    while (const auto line = gateway.read_line(deadline)) {
        std::istringstream in(*line);
        std::string name;
        in >> name;
        if (name.rfind(prefix, 0) != 0) {
            continue;
        }
        // received forwarded queued, then one column per drop reason
        std::vector<unsigned long long> numbers(3 + tgw::core::DROP_REASON_COUNT);
        for (auto& n : numbers) {
            in >> n;
        }
        if (in) {
            rows[name] = numbers;
        }
    }
    return rows;
}

int run(const Options& options) {
    const auto domains = tgw::bench::BenchDomains::for_this_process();
    const std::string prefix = "churn/";
    GatewayReaders readers(prefix);
    TestParticipant robot(domains.robot, TestParticipant::robot_qos(), &readers);
    if (!robot.ok()) {
        std::fprintf(stderr, "publisher_churn_bench: cannot create the robot participant\n");
        return 1;
    }
    const std::string log_file = "/tmp/publisher_churn_bench_" + std::to_string(::getpid()) + ".db";
    std::vector<std::string> argv = {options.gateway,
                                     "--robot-domain",
                                     std::to_string(domains.robot),
                                     "--wan-domain",
                                     std::to_string(domains.wan),
                                     "--wan-peer",
                                     "127.0.0.1:" + std::to_string(domains.wan_reader_port),
                                     "--wan-interface",
                                     "127.0.0.1",
                                     "--wan-port",
                                     std::to_string(domains.gateway_wan_port),
                                     "--sensor",
                                     "fixed:1000000",
                                     "--default-ttl",
                                     std::to_string(options.ttl_s)};
    argv.insert(argv.end(), options.gateway_args.begin(), options.gateway_args.end());
    if (options.no_log) {
        argv.push_back("--no-log");
    } else {
        argv.insert(argv.end(), {"--log", log_file});
    }
    ChildProcess gateway(argv, "/tmp/publisher_churn_bench_" + std::to_string(::getpid()) + ".stderr");
    if (!gateway.started()) {
        std::fprintf(stderr, "publisher_churn_bench: cannot start %s\n", options.gateway.c_str());
        return 1;
    }
    std::this_thread::sleep_for(1s);
    const long started_kb = tgw::bench::rss_kb(std::to_string(gateway.pid()));

    Churn churn(options, robot, readers, prefix);
    CycleFigures warm_up;
    if (!churn.run(0, gateway.pid(), warm_up)) {
        return 1;
    }
    const long baseline_kb = warm_up.gone_kb;
    std::string extra;
    for (const std::string& arg : options.gateway_args) {
        extra += " " + arg;
    }
    std::printf("publisher churn: %d topics a cycle, %d samples each, TTL %d s, %s names, log %s, gateway flags:%s\n",
                options.topics, options.samples, options.ttl_s, options.fresh_names ? "fresh" : "the same",
                options.no_log ? "no" : "yes", extra.empty() ? " none" : extra.c_str());
    std::printf(
        "gateway VmRSS: %ld kB at start; %ld kB with %d topics bridged in the warm-up cycle; baseline %ld kB "
        "after it\n",
        started_kb, warm_up.bridged_kb, options.topics, baseline_kb);
    std::printf("%6s %14s %12s %10s %8s\n", "cycle", "bridged_kB", "gone_kB", "vs_base", "seconds");
    CycleFigures last;
    for (int cycle = 1; cycle <= options.cycles; ++cycle) {
        if (!churn.run(cycle, gateway.pid(), last)) {
            return 1;
        }
        std::printf("%6d %14ld %12ld %+9.1f%% %8.1f\n", cycle, last.bridged_kb, last.gone_kb,
                    100.0 * static_cast<double>(last.gone_kb - baseline_kb) / static_cast<double>(baseline_kb),
                    last.seconds);
        std::fflush(stdout);
    }
    const double growth = 100.0 * static_cast<double>(last.gone_kb - baseline_kb) / static_cast<double>(baseline_kb);

    ::kill(gateway.pid(), SIGTERM);
    const auto rows = summary_rows(gateway, prefix);
    gateway.wait(std::chrono::steady_clock::now() + 10s);
    std::remove(log_file.c_str());
    std::remove((log_file + "-wal").c_str());
    std::remove((log_file + "-shm").c_str());

    const unsigned long long expected =
        static_cast<unsigned long long>(options.samples) * static_cast<unsigned long long>(options.cycles + 1);
    int unaccounted = 0;
    for (const std::string& topic : churn.topics()) {
        const auto it = rows.find(topic);
        const unsigned long long want =
            options.fresh_names ? static_cast<unsigned long long>(options.samples) : expected;
        if (it == rows.end()) {
            std::printf("%s: not in the exit summary\n", topic.c_str());
            ++unaccounted;
            continue;
        }
        const auto& n = it->second;
        unsigned long long dropped = 0;
        for (std::size_t i = 3; i < n.size(); ++i) {
            dropped += n[i];
        }
        if (n[0] != want || n[0] != n[1] + n[2] + dropped) {
            std::printf("%s: received %llu (published %llu), forwarded %llu, queued %llu, dropped %llu\n",
                        topic.c_str(), n[0], want, n[1], n[2], dropped);
            ++unaccounted;
        }
    }
    std::printf("exit summary: %zu of %zu topics, %d with samples unaccounted for\n", rows.size(),
                churn.topics().size(), unaccounted);
    std::printf("resident memory after the last cycle: %+.1f %% of the baseline (limit %.0f %%)\n", growth,
                options.max_growth_percent);
    return growth <= options.max_growth_percent && unaccounted == 0 && rows.size() == churn.topics().size() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    Options options;
    CLI::App app{"publisher_churn_bench: telemetry-gateway's resident memory while robot topics come and go"};
    app.add_option("--gateway", options.gateway, "the telemetry-gateway program")->capture_default_str();
    app.add_option("--topics", options.topics, "topics that appear and disappear each cycle")->capture_default_str();
    app.add_option("--cycles", options.cycles, "cycles after the warm-up one")->capture_default_str();
    app.add_option("--samples", options.samples, "samples each topic publishes a cycle")->capture_default_str();
    app.add_option("--ttl-s", options.ttl_s, "the gateway's --default-ttl")->capture_default_str();
    app.add_flag("--fresh-names", options.fresh_names, "new topic names each cycle (default: the same names)");
    app.add_flag("--no-log", options.no_log, "run the gateway without its on-robot log");
    app.add_option("--max-growth-percent", options.max_growth_percent,
                   "exit 1 when the last cycle ends this far above the baseline")
        ->capture_default_str();
    app.add_option("--timeout-s", options.timeout_s, "how long a cycle's steps may take")->capture_default_str();
    app.add_option("--gateway-arg", options.gateway_args, "a further flag for the gateway, as --gateway-arg=FLAG");
    CLI11_PARSE(app, argc, argv);
    return run(options);
}
