// topic_scale_bench: how long the gateway takes to bridge many robot topics that appear at once, and how it
// forwards with all of them active, in one process on loopback, budget unconstrained.
//
// Method: one robot participant (shared memory and UDP) creates --topics writers, each on its own topic of the
// same type (PaperMessage), as fast as it can. Timed from the first create_datawriter call: all writers
// created, every topic in Gateway::topics() (bridged: WAN writer and robot reader exist), and, with a WAN
// reader per topic created after that, every WAN reader matched. Then each topic publishes at --hz for
// --duration seconds (paced in 1 ms ticks spread over the topics); printed: sent, delivered, delivered/sent and
// the one-way latency (WAN reader's receive time minus source timestamp). Best effort, KEEP_LAST 10 at the
// writers, 100 at the readers. Not run by ctest.
//
// --direct-baseline: first, before the gateway exists, a UDP-only participant in the robot domain creates a reader
// on each topic, as a process would without the gateway, and the time until every reader and every writer matched
// is printed; that participant is then deleted, the gateway made, and its bridging timed from its creation.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "base/config_error.hpp"
#include "test/bench/bench_support.hpp"

namespace {

using namespace std::chrono_literals;
using tgw::bench::CountingReader;
using tgw::test::TestParticipant;
namespace fdds = eprosima::fastdds::dds;

struct Options {
    int topics = 1000;
    double hz = 10;
    double duration_s = 10;
    int timeout_s = 60;
    std::size_t size = 64;
    bool wan_readers = true;
    bool direct_baseline = false;
    tgw::bench::GatewayOptions gateway;
    std::uint32_t reader_receive_buffer_bytes = 0;
};

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Seconds from the first create_datareader of a UDP-only participant in the robot domain, one reader per topic of
/// `writers`, until every reader has matched its writer and every writer a reader; none, after saying so, on a
/// timeout. The participant is deleted before it returns.
std::optional<double> direct_match_seconds(const tgw::bench::BenchDomains& domains,
                                           const std::vector<fdds::DataWriter*>& writers,
                                           const std::function<std::string(int)>& topic_name, fdds::TypeSupport type,
                                           const fdds::DataReaderQos& qos, std::chrono::seconds timeout) {
    TestParticipant direct(domains.robot, tgw::bench::direct_reader_qos(domains));
    if (!direct.ok()) {
        std::fprintf(stderr, "topic_scale_bench: cannot create the direct participant\n");
        return std::nullopt;
    }
    CountingReader listener(false);
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < static_cast<int>(writers.size()); ++i) {
        if (direct.make_reader(topic_name(i), type, qos, &listener) == nullptr) {
            std::fprintf(stderr, "topic_scale_bench: cannot create direct reader %d\n", i);
            return std::nullopt;
        }
    }
    const double created_s = seconds_since(start);
    const bool matched = tgw::test::wait_until(
        [&] {
            if (listener.matched.load() < static_cast<int>(writers.size()))
                return false;
            fdds::PublicationMatchedStatus status;
            for (fdds::DataWriter* writer : writers) {
                writer->get_publication_matched_status(status);
                if (status.current_count == 0)
                    return false;
            }
            return true;
        },
        timeout);
    const double matched_s = seconds_since(start);
    std::printf("%-34s %10.3f\n", "direct: readers created", created_s);
    std::printf("%-34s %10.3f%s\n", "direct: all readers matched", matched_s, matched ? "" : "  TIMEOUT");
    std::fflush(stdout);
    if (!matched)
        return std::nullopt;
    return matched_s;
}

int run(const Options& options) {
    const auto domains = tgw::bench::BenchDomains::for_this_process();
    tgw::test::use_transports_in_process();
    TestParticipant publisher(domains.robot, tgw::bench::publisher_qos());
    TestParticipant basecamp(
        domains.wan,
        tgw::bench::with_receive_buffer(TestParticipant::wan_qos(domains.wan_reader_port, domains.gateway_wan_port),
                                        options.reader_receive_buffer_bytes));
    if (!publisher.ok() || !basecamp.ok()) {
        std::fprintf(stderr, "topic_scale_bench: cannot create the participants\n");
        return 1;
    }
    tgw::base::SystemClock clock;
    // Without a baseline the gateway is there first and sees the writers appear; with one, it comes after them.
    std::optional<tgw::dds::Gateway> gateway;
    if (!options.direct_baseline)
        gateway.emplace(tgw::bench::gateway_config(domains, options.gateway), clock);

    fdds::TypeSupport type(new tgw::idl::PaperMessagePubSubType());
    fdds::DataWriterQos wq = publisher.default_writer_qos();
    wq.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
    wq.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    wq.history().depth = 10;
    wq.data_sharing().off();
    fdds::DataReaderQos rq = basecamp.default_reader_qos();
    rq.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
    rq.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    rq.history().depth = 100;
    rq.data_sharing().off();

    const auto topic_name = [](int i) { return "bench/scale/t" + std::to_string(i); };
    const auto start = std::chrono::steady_clock::now();
    std::vector<fdds::DataWriter*> writers;
    writers.reserve(static_cast<std::size_t>(options.topics));
    for (int i = 0; i < options.topics; ++i) {
        fdds::DataWriter* w = publisher.make_writer(topic_name(i), type, wq);
        if (w == nullptr) {
            std::fprintf(stderr, "topic_scale_bench: cannot create writer %d\n", i);
            return 1;
        }
        writers.push_back(w);
    }
    const double created_s = seconds_since(start);
    const auto timeout = std::chrono::seconds(options.timeout_s);
    const auto n = static_cast<std::size_t>(options.topics);
    std::printf(
        "topic scale: %d robot topics from one participant, loopback, %s; times in s from the "
        "first create_datawriter%s\n",
        options.topics, tgw::bench::describe_unconstrained_budget().c_str(),
        options.direct_baseline ? ", the gateway's from its creation" : "");
    std::printf("%-34s %10.3f\n", "writers created", created_s);
    std::fflush(stdout);
    double direct_s = 0;
    if (options.direct_baseline) {
        const std::optional<double> matched_s = direct_match_seconds(domains, writers, topic_name, type, rq, timeout);
        if (!matched_s)
            return 1;
        direct_s = *matched_s;
    }
    const long before_gateway_kb = tgw::bench::rss_kb();
    const auto bridging_start = options.direct_baseline ? std::chrono::steady_clock::now() : start;
    if (options.direct_baseline) {
        gateway.emplace(tgw::bench::gateway_config(domains, options.gateway), clock);
        std::printf("%-34s %10.3f\n", "gateway made", seconds_since(bridging_start));
    }
    double first_s = -1;
    double half_s = -1;
    const bool bridged = tgw::test::wait_until(
        [&] {
            const std::size_t count = gateway->topics().size();
            if (first_s < 0 && count >= 1)
                first_s = seconds_since(bridging_start);
            if (half_s < 0 && count >= n / 2) {
                half_s = seconds_since(bridging_start);
            }
            return count >= n;
        },
        timeout);
    const double bridged_s = seconds_since(bridging_start);
    std::printf("%-34s %10.3f\n", "first topic bridged", first_s);
    std::printf("%-34s %10.3f\n", "half the topics bridged", half_s);
    std::printf("%-34s %10.3f%s\n", "all topics bridged (topics())", bridged_s, bridged ? "" : "  TIMEOUT");
    std::printf("%-34s %10zu\n", "topics bridged", gateway->topics().size());
    if (options.direct_baseline) {
        std::printf("%-34s %10.2f\n", "bridged / direct matched", direct_s > 0 ? bridged_s / direct_s : 0.0);
        // The gateway's growth, and the publisher's for the gateway's readers: an upper bound per topic.
        std::printf("%-34s %10.1f\n", "process memory per topic, KiB",
                    static_cast<double>(tgw::bench::rss_kb() - before_gateway_kb) / options.topics);
    }
    std::fflush(stdout);
    if (!bridged || !options.wan_readers) {
        return bridged ? 0 : 1;
    }

    CountingReader listener(true);
    std::vector<fdds::DataReader*> readers;
    const auto readers_start = std::chrono::steady_clock::now();
    for (int i = 0; i < options.topics; ++i) {
        readers.push_back(basecamp.make_reader(topic_name(i), type, rq, &listener));
    }
    // Both ends: a reader matches when it learns of the writer, the gateway's WAN writer when it learns of the
    // reader, and the writer sends to no one until then (best effort: those samples are lost for good).
    const bool matched = tgw::test::wait_until(
        [&] {
            if (listener.matched.load() < options.topics) {
                return false;
            }
            for (int i = 0; i < options.topics; ++i) {
                const auto topic = gateway->find_topic(topic_name(i));
                if (!topic || gateway->wan_matched_readers(topic->id) == 0) {
                    return false;
                }
            }
            return true;
        },
        timeout);
    std::printf("%-34s %10.3f%s\n", "WAN readers created and matched", seconds_since(readers_start),
                matched ? "" : "  TIMEOUT");
    std::printf("%-34s %10.3f\n", "  (since first create_datawriter)", seconds_since(start));
    std::fflush(stdout);

    tgw::idl::PaperMessage message;
    message.data().assign(
        options.size > tgw::bench::PAPER_MESSAGE_FIXED_BYTES ? options.size - tgw::bench::PAPER_MESSAGE_FIXED_BYTES : 0,
        0x5a);
    const double total_rate = options.hz * options.topics;
    const tgw::core::TopicCounters gateway_before = gateway->total_counters();
    const auto datagrams_before = gateway->wan_datagrams();
    const auto write_start = std::chrono::steady_clock::now();
    auto next = write_start;
    std::uint64_t sent = 0;
    const auto planned = static_cast<std::uint64_t>(total_rate * options.duration_s);
    while (sent < planned) {
        const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - write_start).count();
        const auto due = std::min(planned, static_cast<std::uint64_t>(total_rate * (elapsed_s + 0.001)));
        while (sent < due) {
            message.sequence_number(static_cast<std::uint32_t>(sent));
            writers[sent % n]->write(&message);
            ++sent;
        }
        next += 1ms;
        std::this_thread::sleep_until(next);
    }
    const double wrote_s = seconds_since(write_start);
    tgw::bench::settle([&] { return listener.received(); }, 500ms);
    const std::uint64_t got = listener.received();
    const auto latencies = listener.latencies_ns();
    std::printf("forwarding: %d topics at %.1f Hz (%.0f samples/s, %zu bytes) for %.1f s (wrote in %.2f s)\n",
                options.topics, options.hz, total_rate, options.size, options.duration_s, wrote_s);
    std::printf("%10s %10s %9s %9s %9s %9s\n", "sent", "delivered", "ratio", "lat50_us", "lat99_us", "latmax_us");
    std::printf("%10llu %10llu %9.4f %9.1f %9.1f %9.1f\n", static_cast<unsigned long long>(sent),
                static_cast<unsigned long long>(got),
                sent > 0 ? static_cast<double>(got) / static_cast<double>(sent) : 0.0,
                tgw::bench::percentile_us(latencies, 0.5), tgw::bench::percentile_us(latencies, 0.99),
                tgw::bench::percentile_us(latencies, 1.0));
    // Where a loss happened: before the gateway, in it, or after it.
    const tgw::core::TopicCounters in_gateway = gateway->total_counters();
    const auto datagrams = gateway->wan_datagrams();
    std::printf("gateway: %llu received, %llu forwarded, in %llu WAN datagrams (%llu failed)\n",
                static_cast<unsigned long long>(in_gateway.received - gateway_before.received),
                static_cast<unsigned long long>(in_gateway.forwarded - gateway_before.forwarded),
                static_cast<unsigned long long>(datagrams.datagrams - datagrams_before.datagrams),
                static_cast<unsigned long long>(datagrams.failed_datagrams - datagrams_before.failed_datagrams));
    std::fflush(stdout);
    for (auto* r : readers) {
        r->set_listener(nullptr);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"topic_scale_bench: time to bridge many robot topics, then forwarding with all active, loopback"};
    Options options;
    app.add_option("--topics", options.topics, "robot topics (one writer each)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--hz", options.hz, "samples/s per topic while forwarding")->capture_default_str();
    app.add_option("--duration", options.duration_s, "seconds of forwarding")->capture_default_str();
    app.add_option("--size", options.size, "serialized sample size in bytes")->capture_default_str();
    app.add_option("--timeout", options.timeout_s, "seconds to wait for bridging and matching")->capture_default_str();
    app.add_flag("!--no-wan-readers", options.wan_readers, "measure bridging only");
    app.add_flag("--direct-baseline", options.direct_baseline,
                 "first time a UDP-only participant matching every writer with a reader of its own, then the gateway "
                 "bridging the same writers from its creation");
    app.add_option("--reader-receive-buffer", options.reader_receive_buffer_bytes,
                   "SO_RCVBUF of the base camp's participant, bytes; 0: the system's default")
        ->capture_default_str();
    options.gateway.add_flags(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    try {
        return run(options);
    } catch (const tgw::base::ConfigError& e) {
        std::fprintf(stderr, "topic_scale_bench: %s\n", e.what());
        return 1;
    }
}
