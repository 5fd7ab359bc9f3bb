// throughput_bench: the largest sample rate the gateway forwards without loss, against direct Fast DDS, in one
// process on loopback, budget unconstrained (100 Gbit/s, default TTL policy).
//
// Method: for each size, the offered rate steps up geometrically (x1.5) from --start-rate. At each step the
// robot publisher (shared memory and UDP) writes PaperMessage samples for --duration seconds, paced in 1 ms
// batches, first on a topic read directly by a UDP-only reader in the robot domain, then on a topic the
// Gateway bridges to a UDP-only reader in the WAN domain; after each burst the reader is let drain (200 ms
// quiet). A path's figure is the highest offered rate at which its loss was below --max-loss. Both paths use
// the same QoS: best effort, KEEP_LAST 100 at the writer (transient local, Fast DDS's default, or volatile with
// --volatile), KEEP_LAST 1000 at the readers, data sharing off.
// A path stops stepping after two lossy steps in a row, or once the publisher cannot write at the offered
// rate (then the figure is a floor). Then --bisect steps halve (geometrically) the gap between each path's
// last loss-free and first lossy rate. At the highest rate both paths carried, each path's CPU per sample is
// given for the whole process and for its busiest thread (from the kernel's per-thread run time): a path cannot
// carry more than 1 s over the latter a second, whatever the number of cores. Not run by ctest.
#include <CLI/CLI.hpp>

#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>

#include "base/receive_buffer.hpp"
#include "test/bench/bench_support.hpp"
#include "test/bench/side_by_side.hpp"
#include "test/bench/thread_cpu.hpp"

namespace {

using namespace std::chrono_literals;
using tgw::bench::CountingReader;
namespace fdds = eprosima::fastdds::dds;

struct Options {
    std::vector<std::size_t> sizes{64, 65536};
    double duration_s = 1.0;
    double start_rate = 1000;
    double max_rate = 2e6;
    double max_loss = 0.001;
    bool verbose = false;
    bool volatile_writer = false;
    std::uint32_t direct_max_message_bytes = 0;
    int bisect_steps = 3;
    int repeat = 1;
    tgw::bench::GatewayOptions gateway{tgw::core::WireModel::MAX_UDP_PAYLOAD_BYTES};
    /// As the camp's tools have it (tm-basecamp --receive-buffer), on both paths alike.
    std::uint32_t reader_receive_buffer_bytes = tgw::base::DEFAULT_RECEIVE_BUFFER_BYTES;
};

/// ", expired 3, write_failed 12": the gateway's drops between two readings of its counters, by reason.
std::string drop_reasons(const tgw::core::TopicCounters& now, const tgw::core::TopicCounters& before) {
    std::string out;
    for (std::size_t r = 0; r < tgw::core::DROP_REASON_COUNT; ++r) {
        const auto reason = static_cast<tgw::core::DropReason>(r);
        const std::uint64_t n = now.dropped_for(reason) - before.dropped_for(reason);
        if (n > 0) {
            out += ", " + std::string(tgw::core::to_string(reason)) + " " + std::to_string(n);
        }
    }
    return out;
}

/// "writer 30.2, reader 16.4, 4711 46.5": the three threads that used the most CPU per sample, busiest first; the
/// bench's own thread (the writer's) and the reader's named, the gateway's and Fast DDS's by thread id.
std::string describe_busiest(const std::map<pid_t, double>& us_per_sample, pid_t reader_thread) {
    std::vector<std::pair<double, pid_t>> busiest;
    for (const auto& [tid, us] : us_per_sample) {
        busiest.emplace_back(us, tid);
    }
    std::sort(busiest.rbegin(), busiest.rend());
    std::string out;
    for (std::size_t i = 0; i < std::min<std::size_t>(busiest.size(), 3); ++i) {
        const auto [us, tid] = busiest[i];
        const std::string name = tid == ::getpid() ? "writer" : tid == reader_thread ? "reader" : std::to_string(tid);
        char figure[32];
        std::snprintf(figure, sizeof figure, "%.1f", us);
        out += (i > 0 ? ", " : "") + name + " " + figure;
    }
    return out;
}

class Bench {
  public:
    explicit Bench(const Options& options)
        : options_(options), domains_(tgw::bench::BenchDomains::for_this_process()) {}

    bool set_up() {
        return side_.set_up("throughput_bench", domains_, tgw::bench::publisher_qos(options_.direct_max_message_bytes),
                            tgw::bench::direct_reader_qos(domains_),
                            tgw::bench::gateway_config(domains_, options_.gateway), clock_,
                            options_.reader_receive_buffer_bytes);
    }

    bool run(std::size_t size) {
        CountingReader via_reader;
        CountingReader direct_reader;
        const auto pair = side_.open_pair("throughput_bench", "bench/gateway/tput/" + std::to_string(size),
                                          "bench/direct/tput/" + std::to_string(size),
                                          side_.writer_qos(false, options_.volatile_writer), side_.reader_qos(false),
                                          side_.reader_qos(false), via_reader, direct_reader, 10s);
        if (!pair) {
            return false;
        }
        tgw::idl::PaperMessage message;
        message.data().assign(
            size > tgw::bench::PAPER_MESSAGE_FIXED_BYTES ? size - tgw::bench::PAPER_MESSAGE_FIXED_BYTES : 0, 0x5a);
        for (int run = 1; run <= options_.repeat; ++run) {
            Path direct_path{"direct", pair->direct_writer, direct_reader, std::nullopt};
            Path via_path{"gateway", pair->via_writer, via_reader, pair->id};
            search(direct_path, via_path, message);
            const double mb = static_cast<double>(size) / 1e6;
            const double cpu_rate = common_loss_free_rate(direct_path, via_path);
            const CpuPerSample direct_cpu = cpu_rate > 0 ? direct_path.cpu_at_rate.at(cpu_rate) : CpuPerSample{};
            const CpuPerSample via_cpu = cpu_rate > 0 ? via_path.cpu_at_rate.at(cpu_rate) : CpuPerSample{};
            std::printf("%8zu %4d %12.0f%s %10.1f %12.0f%s %10.1f %7.2f %8.0f %13.1f %10.1f %13.1f %10.1f\n", size, run,
                        direct_path.best_rate, direct_path.writer_bound ? "+" : " ", direct_path.best_rate * mb,
                        via_path.best_rate, via_path.writer_bound ? "+" : " ", via_path.best_rate * mb,
                        direct_path.best_rate > 0 ? via_path.best_rate / direct_path.best_rate : 0.0, cpu_rate,
                        direct_cpu.process_us, via_cpu.process_us, direct_cpu.busiest_thread_us,
                        via_cpu.busiest_thread_us);
            std::fflush(stdout);
        }
        return true;
    }

    void tear_down() { side_.tear_down(); }

  private:
    static constexpr double RAMP_FACTOR = 1.5;
    /// A step whose publisher achieved less than this fraction of the offered rate measures the publisher.
    static constexpr double WRITER_BOUND_FRACTION = 0.9;

    /// CPU time per sample of a step.
    struct CpuPerSample {
        double process_us = 0;  ///< every thread: writer, gateway, reader
        /// The thread that used the most: the path carries at most 1 s over it a second.
        double busiest_thread_us = 0;
    };

    /// One path under test and where its search stands.
    struct Path {
        const char* name;
        fdds::DataWriter* writer;
        CountingReader& reader;
        std::optional<tgw::core::TopicId> gateway_topic;  ///< set for the path through the gateway
        double best_rate = 0;                             ///< the highest loss-free rate so far
        std::map<double, CpuPerSample> cpu_at_rate{};     ///< at each loss-free ramp rate
        double first_lossy_rate = 0;                      ///< the lowest lossy rate above best_rate, 0 while none
        int lossy_in_a_row = 0;
        bool writer_bound = false;
        bool done = false;
    };

    /// The highest ramp rate both paths carried without loss, where their CPU per sample compares; 0 if none.
    static double common_loss_free_rate(const Path& direct, const Path& via) {
        for (auto it = direct.cpu_at_rate.rbegin(); it != direct.cpu_at_rate.rend(); ++it) {
            if (via.cpu_at_rate.count(it->first) != 0)
                return it->first;
        }
        return 0;
    }

    struct Step {
        double loss = 1.0;
        double achieved = 0;
        CpuPerSample cpu;
    };

    /// CPU seconds this process has used, user and system, every thread.
    static double process_cpu_s() {
        rusage usage{};
        ::getrusage(RUSAGE_SELF, &usage);
        const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + t.tv_usec / 1e6; };
        return seconds(usage.ru_utime) + seconds(usage.ru_stime);
    }

    /// Offers `rate` on the path for the duration and counts what arrived once the reader has drained.
    Step measure(Path& path, tgw::idl::PaperMessage& message, double rate) {
        const std::uint64_t before = path.reader.received();
        tgw::core::TopicCounters gw_before;
        if (path.gateway_topic) {
            gw_before = side_.gateway().counters(*path.gateway_topic);
        }
        const double cpu_before_s = process_cpu_s();
        const tgw::bench::ThreadCpu threads_before = tgw::bench::ThreadCpu::now();
        const auto [sent, achieved] = burst(path.writer, message, rate, sequence_);
        tgw::bench::settle([&] { return path.reader.received(); });
        const std::uint64_t got = path.reader.received() - before;
        Step step;
        step.loss = sent == 0 ? 1.0 : 1.0 - static_cast<double>(got) / static_cast<double>(sent);
        step.achieved = achieved;
        step.cpu.process_us = sent == 0 ? 0 : (process_cpu_s() - cpu_before_s) * 1e6 / static_cast<double>(sent);
        const std::map<pid_t, double> threads = tgw::bench::ThreadCpu::now().us_per_sample_since(threads_before, sent);
        for (const auto& [tid, us] : threads) {
            step.cpu.busiest_thread_us = std::max(step.cpu.busiest_thread_us, us);
        }
        if (options_.verbose) {
            // Where a gateway-path sample was lost: before the gateway (robot side), in it, or after.
            tgw::core::TopicCounters gw;
            if (path.gateway_topic) {
                gw = side_.gateway().counters(*path.gateway_topic);
            }
            std::fprintf(stderr,
                         "  %-7s offered %9.0f/s achieved %9.0f/s sent %8llu got %8llu cpu %.1f us/sample "
                         "(gateway in %llu fwd %llu dropped %llu%s)\n",
                         path.name, rate, achieved, static_cast<unsigned long long>(sent),
                         static_cast<unsigned long long>(got), step.cpu.process_us,
                         static_cast<unsigned long long>(gw.received - gw_before.received),
                         static_cast<unsigned long long>(gw.forwarded - gw_before.forwarded),
                         static_cast<unsigned long long>(gw.dropped_total() - gw_before.dropped_total()),
                         drop_reasons(gw, gw_before).c_str());
            std::fprintf(stderr, "          threads, us/sample: %s\n",
                         describe_busiest(threads, path.reader.listener_thread()).c_str());
        }
        return step;
    }

    /// Both paths' highest loss-free rates: a ramp, then bisection.
    void search(Path& direct_path, Path& via_path, tgw::idl::PaperMessage& message) {
        // Ramp: both paths step up together, so that the machine's noise falls on both alike.
        for (double rate = options_.start_rate; rate <= options_.max_rate && !(direct_path.done && via_path.done);
             rate *= RAMP_FACTOR) {
            for (Path* path : {&direct_path, &via_path}) {
                if (!path->done) {
                    ramp_step(*path, message, rate);
                }
            }
        }
        // Bisection: between the last loss-free rate and the first lossy one, the ramp's x1.5 steps would
        // quantise the ratio to powers of 1.5.
        for (int i = 0; i < options_.bisect_steps; ++i) {
            for (Path* path : {&direct_path, &via_path}) {
                if (path->writer_bound || path->best_rate <= 0 || path->first_lossy_rate <= 0) {
                    continue;
                }
                const double rate = std::sqrt(path->best_rate * path->first_lossy_rate);
                const Step step = measure(*path, message, rate);
                if (step.loss < options_.max_loss && step.achieved >= WRITER_BOUND_FRACTION * rate) {
                    path->best_rate = rate;
                } else {
                    path->first_lossy_rate = rate;
                }
            }
        }
    }

    /// One ramp step: a path stops after two lossy steps in a row, or once its publisher cannot keep up
    /// (then best_rate is a floor).
    void ramp_step(Path& path, tgw::idl::PaperMessage& message, double rate) {
        const Step step = measure(path, message, rate);
        if (step.loss < options_.max_loss) {
            path.lossy_in_a_row = 0;
            if (step.achieved < WRITER_BOUND_FRACTION * rate) {
                path.writer_bound = true;
                path.done = true;
            } else {
                path.best_rate = rate;
                path.cpu_at_rate[rate] = step.cpu;
                path.first_lossy_rate = 0;
            }
            return;
        }
        if (path.first_lossy_rate <= 0) {
            path.first_lossy_rate = rate;
        }
        if (++path.lossy_in_a_row >= 2) {
            path.done = true;
        }
    }

    /// Writes at `rate` samples/s for the duration, in 1 ms batches. Returns the samples written and the rate
    /// achieved.
    std::pair<std::uint64_t, double> burst(fdds::DataWriter* writer, tgw::idl::PaperMessage& message, double rate,
                                           std::uint32_t& sequence) {
        const auto start = std::chrono::steady_clock::now();
        const auto end = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(options_.duration_s));
        std::uint64_t sent = 0;
        auto next = start;
        while (true) {
            const auto now = std::chrono::steady_clock::now();
            if (now >= end) {
                break;
            }
            const double elapsed_s = std::chrono::duration<double>(now - start).count();
            const auto due = static_cast<std::uint64_t>(rate * std::min(elapsed_s + 0.001, options_.duration_s));
            while (sent < due) {
                message.sequence_number(sequence++);
                writer->write(&message);
                ++sent;
            }
            next += 1ms;
            std::this_thread::sleep_until(next);
        }
        const double took_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return {sent, static_cast<double>(sent) / std::max(took_s, options_.duration_s)};
    }

    Options options_;
    tgw::bench::BenchDomains domains_;
    tgw::base::SystemClock clock_;
    tgw::bench::SideBySide side_;
    std::uint32_t sequence_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"throughput_bench: highest loss-free sample rate via the gateway against direct Fast DDS, loopback"};
    Options options;
    app.add_option("--sizes", options.sizes, "serialized sample sizes in bytes")->capture_default_str();
    app.add_option("--duration", options.duration_s, "seconds of writing per step and path")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--start-rate", options.start_rate, "first offered rate, samples/s")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--max-rate", options.max_rate, "highest offered rate, samples/s")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--max-loss", options.max_loss, "loss fraction still counted as lossless")->capture_default_str();
    app.add_option("--direct-max-message", options.direct_max_message_bytes,
                   "the publisher's UDP maxMessageSize (the direct path's datagrams); 1472 fragments as the "
                   "gateway's WAN participant does; default 0: Fast DDS's 65500")
        ->capture_default_str();
    app.add_option("--bisect", options.bisect_steps,
                   "bisection steps between the last loss-free and the first lossy ramp rate")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--repeat", options.repeat, "searches per size, a row each: the figure is noisy near the threshold")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    options.gateway.add_flags(app);
    app.add_option("--reader-receive-buffer", options.reader_receive_buffer_bytes,
                   "SO_RCVBUF of both readers' participants, bytes, as tm-basecamp's --receive-buffer; 0: the system's "
                   "default (the gateway's robot side has its own, --robot-receive-buffer)")
        ->capture_default_str();
    tgw::bench::add_volatile_flag(app, options.volatile_writer);
    app.add_flag("--verbose", options.verbose, "print every step to stderr");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    Bench bench(options);
    if (!bench.set_up()) {
        return 1;
    }
    std::printf(
        "throughput: highest offered rate with loss < %.2f %%, steps x1.5 of %.1f s then %d bisections, best effort, "
        "writer KEEP_LAST 100 %s, readers KEEP_LAST 1000, direct reader UDP, %s, %s, "
        "direct path's datagrams up to %s B; '+': publisher-bound floor; *_max_us: the CPU per sample of the path's "
        "busiest thread, which bounds its rate\n",
        options.max_loss * 100, options.duration_s, options.bisect_steps,
        options.volatile_writer ? "volatile" : "transient local", options.gateway.describe().c_str(),
        tgw::bench::describe_unconstrained_budget().c_str(),
        options.direct_max_message_bytes > 0 ? std::to_string(options.direct_max_message_bytes).c_str() : "65500");
    std::printf("%8s %4s %13s %10s %13s %10s %7s %8s %13s %10s %13s %10s\n", "bytes", "run", "direct/s", "direct_MB/s",
                "via_gw/s", "via_MB/s", "ratio", "cpu_at/s", "direct_cpu_us", "via_cpu_us", "direct_max_us",
                "via_max_us");
    int rc = 0;
    for (std::size_t size : options.sizes) {
        if (!bench.run(size)) {
            rc = 1;
            break;
        }
    }
    bench.tear_down();
    return rc;
}
