// gateway_hop_bench: what the gateway costs a sample, in one process on loopback, budget unconstrained.
//
// A robot-domain publisher (shared memory and UDP on 127.0.0.1, as a robot process) writes PaperMessage samples
// at a steady pace, alternating between two topics: one the Gateway bridges to a UDP-only reader in the WAN
// domain, one read directly by the same kind of UDP-only reader in the robot domain (the gateway denies it).
// Both paths run in the same time window, so machine noise hits them alike. Printed per sample size: the
// gateway's own processing time (its LatencyHistogram: arrival to the return of the WAN write), and the
// one-way latency (reader's receive time minus the source timestamp) via the gateway and direct, with the
// ratio. Not run by ctest; scripts/bench runs it.
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>

#include "PaperWorkloadPubSubTypes.h"
#include "base/clock.hpp"
#include "gateway/dds/gateway.hpp"
#include "passthrough/dds_time.hpp"
#include "test/bench/bench_support.hpp"
#include "test/bench/side_by_side.hpp"
#include "test/integration/dds_test_support.hpp"

namespace {

using namespace std::chrono_literals;
using tgw::test::fdds::DataWriter;
using tgw::test::fdds::DomainParticipantQos;
namespace fdds = eprosima::fastdds::dds;
using tgw::bench::BenchDomains;
using tgw::bench::DIRECT_READER_PARTICIPANT_ID;
using tgw::bench::loopback;
using tgw::bench::PAPER_MESSAGE_FIXED_BYTES;
using tgw::bench::percentile_us;
using tgw::bench::PUBLISHER_PARTICIPANT_ID;
using tgw::bench::publisher_qos;

constexpr auto MATCH_TIMEOUT = 10s;

struct Options {
    std::vector<std::size_t> sizes{32, 4096};
    int samples = 20'000;
    int warmup = 1'000;
    int period_us = 250;
    int repeat = 1;
    bool direct_shm = false;
    bool reliable = false;
    bool volatile_writer = false;
    tgw::bench::GatewayOptions gateway;
};

/// The direct reader: UDP only, as a base-camp process would read without the gateway, or with shared memory too,
/// as the gateway's robot reader does.
DomainParticipantQos direct_reader_qos(const BenchDomains& d, bool shm) {
    if (!shm) {
        return tgw::bench::direct_reader_qos(d);
    }
    DomainParticipantQos qos = publisher_qos();
    qos.name("bench/direct");
    qos.wire_protocol().participant_id = DIRECT_READER_PARTICIPANT_ID;
    return qos;
}

/// Records, for every sample past the warm-up, its one-way latency: receive wall time minus source timestamp.
class LatencyReader final : public fdds::DataReaderListener {
  public:
    explicit LatencyReader(int warmup) : warmup_(warmup) {}

    void on_data_available(fdds::DataReader* reader) override {
        fdds::SampleInfo info;
        while (reader->take_next_sample(&data_, &info) == ReturnCode_t::RETCODE_OK) {
            const auto received = tgw::base::WallClock::now();
            if (!info.valid_data) {
                continue;
            }
            const auto source = tgw::passthrough::to_wall_time(info.source_timestamp);
            received_.fetch_add(1);
            if (!source || static_cast<int>(data_.sequence_number()) < warmup_) {
                continue;
            }
            std::lock_guard<std::mutex> lock(mutex_);
            latencies_ns_.push_back(std::chrono::duration_cast<std::chrono::nanoseconds>(received - *source).count());
        }
    }
    void on_subscription_matched(fdds::DataReader*, const fdds::SubscriptionMatchedStatus& info) override {
        matched.store(info.current_count);
    }

    std::uint64_t received() const { return received_.load(); }
    std::vector<std::int64_t> latencies_ns() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return latencies_ns_;
    }

    std::atomic<int> matched{0};

  private:
    const int warmup_;
    tgw::idl::PaperMessage data_;  // one receive thread per reader
    std::atomic<std::uint64_t> received_{0};
    mutable std::mutex mutex_;
    std::vector<std::int64_t> latencies_ns_;
};

double us(tgw::base::Duration d) {
    return std::chrono::duration<double, std::micro>(d).count();
}

class Bench {
  public:
    explicit Bench(const Options& options) : options_(options), domains_(BenchDomains::for_this_process()) {}

    bool set_up() {
        return side_.set_up("gateway_hop_bench", domains_, publisher_qos(),
                            direct_reader_qos(domains_, options_.direct_shm),
                            tgw::bench::gateway_config(domains_, options_.gateway), clock_);
    }

    /// One row: `size` bytes of serialized payload, the samples of both paths interleaved.
    bool run(std::size_t size, int run) {
        const std::string suffix = std::to_string(size) + "/" + std::to_string(run);
        const std::string via_topic = "bench/gateway/" + suffix;
        const std::string direct_topic = "bench/direct/" + suffix;
        auto via_reader = std::make_unique<LatencyReader>(options_.warmup);
        auto direct_reader = std::make_unique<LatencyReader>(options_.warmup);
        // The direct reader is what the gateway's robot reader is: reliable when the publisher is.
        const auto pair = side_.open_pair(
            "gateway_hop_bench", via_topic, direct_topic, side_.writer_qos(options_.reliable, options_.volatile_writer),
            side_.reader_qos(false), side_.reader_qos(options_.reliable), *via_reader, *direct_reader, MATCH_TIMEOUT);
        if (!pair) {
            return false;
        }
        DataWriter* const via_writer = pair->via_writer;
        DataWriter* const direct_writer = pair->direct_writer;

        tgw::idl::PaperMessage message;
        message.data().assign(size > PAPER_MESSAGE_FIXED_BYTES ? size - PAPER_MESSAGE_FIXED_BYTES : 0, 0x5a);
        const auto period = std::chrono::microseconds(options_.period_us);
        auto next = std::chrono::steady_clock::now();
        const auto publish = [&](int first, int end) {
            for (int i = first; i < end; ++i) {
                message.sequence_number(static_cast<std::uint32_t>(i));
                for (DataWriter* writer : {via_writer, direct_writer}) {
                    next += period;
                    std::this_thread::sleep_until(next);
                    message.generated_ns(static_cast<std::uint64_t>(tgw::base::to_ns(tgw::base::WallClock::now())));
                    writer->write(&message);
                }
            }
        };
        publish(0, options_.warmup);
        // Let the warm-up drain, then count only what follows.
        tgw::bench::settle([&] { return via_reader->received() + direct_reader->received(); });
        const auto before = side_.gateway().processing_latency();
        next = std::chrono::steady_clock::now();
        publish(options_.warmup, options_.warmup + options_.samples);
        tgw::bench::settle([&] { return via_reader->received() + direct_reader->received(); });
        const auto processing = side_.gateway().processing_latency().since(before);

        const auto via_ns = via_reader->latencies_ns();
        const auto direct_ns = direct_reader->latencies_ns();
        const double via_p50 = percentile_us(via_ns, 0.5);
        const double direct_p50 = percentile_us(direct_ns, 0.5);
        std::printf(
            "%6zu %4d %8.1f %8.1f %8.1f %9.1f %9.1f %9.1f %9.1f %9.1f %7.2f %7zu %7zu\n", size, run,
            us(processing.median()), us(processing.percentile(0.9)), us(processing.percentile(0.99)), direct_p50,
            percentile_us(direct_ns, 0.99), via_p50, percentile_us(via_ns, 0.99), via_p50 - direct_p50,
            direct_p50 > 0 ? via_p50 / direct_p50 : 0.0,
            static_cast<std::size_t>(options_.samples) - std::min<std::size_t>(options_.samples, via_ns.size()),
            static_cast<std::size_t>(options_.samples) - std::min<std::size_t>(options_.samples, direct_ns.size()));
        std::fflush(stdout);
        return true;
    }

    void tear_down() { side_.tear_down(); }

  private:
    Options options_;
    BenchDomains domains_;
    tgw::base::SystemClock clock_;
    tgw::bench::SideBySide side_;
};

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"gateway_hop_bench: the gateway's processing time and added one-way latency, loopback"};
    Options options;
    app.add_option("--size", options.sizes, "serialized sample sizes in bytes; repeatable")->capture_default_str();
    app.add_option("--samples", options.samples, "samples per path and size, after the warm-up")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--warmup", options.warmup, "samples per path left out at the start")->capture_default_str();
    app.add_option("--period-us", options.period_us, "microseconds between two writes (the paths alternate)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--repeat", options.repeat, "rows per size")->check(CLI::PositiveNumber)->capture_default_str();
    app.add_flag("--direct-shm", options.direct_shm,
                 "the direct reader uses shared memory, as the gateway's robot reader does (default: UDP, as a "
                 "base-camp reader would)");
    options.gateway.add_flags(app);
    app.add_flag("--reliable", options.reliable,
                 "reliable publisher (the gateway's robot reader and the direct reader follow; default: best effort)");
    tgw::bench::add_volatile_flag(app, options.volatile_writer);
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
        "gateway hop: %d samples per path, one every %d us per path, %s%s publisher, direct reader on %s, %s, "
        "loopback, budget unconstrained; times in us\n",
        options.samples, 2 * options.period_us, options.reliable ? "reliable" : "best-effort",
        options.volatile_writer ? " volatile" : " transient-local", options.direct_shm ? "shared memory" : "UDP",
        options.gateway.describe().c_str());
    std::printf("%6s %4s %8s %8s %8s %9s %9s %9s %9s %9s %7s %7s %7s\n", "bytes", "run", "proc50", "proc90", "proc99",
                "direct50", "direct99", "via_gw50", "via_gw99", "added50", "ratio", "lost_gw", "lost_dir");
    int rc = 0;
    for (int run = 1; run <= options.repeat && rc == 0; ++run) {
        for (std::size_t size : options.sizes) {
            if (!bench.run(size, run)) {
                rc = 1;
                break;
            }
        }
    }
    bench.tear_down();
    return rc;
}
