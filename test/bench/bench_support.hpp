// Shared by the DDS benches (gateway_hop_bench, throughput_bench, topic_scale_bench): the domains of this
// process, loopback locators, the robot publisher's and the UDP-only direct reader's participant QoS, and a
// counting reader.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <CLI/CLI.hpp>

#include "PaperWorkloadPubSubTypes.h"
#include "base/clock.hpp"
#include "gateway/dds/gateway.hpp"
#include "passthrough/dds_time.hpp"
#include "test/integration/dds_test_support.hpp"

namespace tgw::bench {

namespace fdds = eprosima::fastdds::dds;

/// Encapsulation (4) + generated_ns (8) + sequence_number (4) + sequence length (4): a PaperMessage's bytes
/// before its data.
constexpr std::size_t PAPER_MESSAGE_FIXED_BYTES = 20;
constexpr int PUBLISHER_PARTICIPANT_ID = 70;
constexpr int DIRECT_READER_PARTICIPANT_ID = 71;

/// Domains and ports of this process: a pair in 200..229 from the process id.
struct BenchDomains {
    int robot = 0;
    int wan = 0;
    std::uint16_t wan_reader_port = 0;
    std::uint16_t gateway_wan_port = 0;
    std::uint16_t publisher_port = 0;

    static BenchDomains for_this_process() {
        BenchDomains d;
        d.robot = 200 + static_cast<int>(::getpid() % 15) * 2;
        d.wan = d.robot + 1;
        d.wan_reader_port = base::metatraffic_unicast_port(d.wan, 60);
        d.gateway_wan_port = base::metatraffic_unicast_port(d.wan, 61);
        d.publisher_port = base::metatraffic_unicast_port(d.robot, PUBLISHER_PARTICIPANT_ID);
        return d;
    }
};

inline eprosima::fastrtps::rtps::Locator_t loopback(std::uint16_t port) {
    eprosima::fastrtps::rtps::Locator_t l;
    l.kind = LOCATOR_KIND_UDPv4;
    eprosima::fastrtps::rtps::IPLocator::setIPv4(l, "127.0.0.1");
    l.port = port;
    return l;
}

/// A robot process: shared memory and UDP on loopback, a fixed participant id. `udp_max_message_bytes` 0:
/// Fast DDS's default (65500).
inline fdds::DomainParticipantQos publisher_qos(std::uint32_t udp_max_message_bytes = 0) {
    fdds::DomainParticipantQos qos;
    qos.name("bench/publisher");
    qos.wire_protocol().participant_id = PUBLISHER_PARTICIPANT_ID;
    qos.transport().use_builtin_transports = false;
    qos.transport().user_transports.push_back(
        std::make_shared<eprosima::fastdds::rtps::SharedMemTransportDescriptor>());
    auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
    udp->interfaceWhiteList.push_back("127.0.0.1");
    if (udp_max_message_bytes > 0) {
        udp->maxMessageSize = udp_max_message_bytes;
    }
    qos.transport().user_transports.push_back(udp);
    return qos;
}

/// VmRSS of process `pid` (this one by default) in kB; 0 when it cannot be read.
inline long rss_kb(const std::string& pid = "self") {
    std::ifstream status("/proc/" + pid + "/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmRSS:", 0) == 0) {
            return std::stol(line.substr(6));
        }
    }
    return 0;
}

/// `qos` with SO_RCVBUF of `bytes` on its UDP transports; 0 leaves the system's default.
inline fdds::DomainParticipantQos with_receive_buffer(fdds::DomainParticipantQos qos, std::uint32_t bytes) {
    if (bytes == 0) {
        return qos;
    }
    for (auto& transport : qos.transport().user_transports) {
        if (auto udp = std::dynamic_pointer_cast<eprosima::fastdds::rtps::UDPv4TransportDescriptor>(transport)) {
            auto resized = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>(*udp);
            resized->receiveBufferSize = bytes;
            transport = resized;
        }
    }
    return qos;
}

/// A subscriber reaching the robot domain over UDP only, as a base-camp process would without the gateway.
inline fdds::DomainParticipantQos direct_reader_qos(const BenchDomains& d) {
    fdds::DomainParticipantQos qos;
    qos.name("bench/direct");
    qos.wire_protocol().participant_id = DIRECT_READER_PARTICIPANT_ID;
    qos.transport().use_builtin_transports = false;
    auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
    udp->interfaceWhiteList.push_back("127.0.0.1");
    qos.transport().user_transports.push_back(udp);
    qos.wire_protocol().builtin.metatrafficUnicastLocatorList.push_back(
        loopback(base::metatraffic_unicast_port(d.robot, DIRECT_READER_PARTICIPANT_ID)));
    qos.wire_protocol().builtin.initialPeersList.push_back(loopback(d.publisher_port));
    return qos;
}

/// The gateway flags a side-by-side bench can set.
struct GatewayOptions {
    std::size_t wan_max_datagram_bytes = 0;  ///< 0: the gateway's default (one Ethernet frame)
    bool robot_shm = false;
    std::int64_t wan_coalesce_us = tgw::dds::DatagramCoalescer::DEFAULT_WINDOW.count();
    std::string log_file{};  ///< empty: no on-robot log

    /// Adds the flags above, as the gateway names them, to a bench's command line.
    void add_flags(CLI::App& app) {
        app.add_option("--wan-coalesce-us", wan_coalesce_us,
                       "the gateway's --wan-coalesce-us: how long a WAN sample that follows closely may wait to "
                       "share a datagram; 0: never")
            ->capture_default_str();
        app.add_option("--wan-max-datagram", wan_max_datagram_bytes,
                       "the gateway's --wan-max-datagram: its largest WAN datagram, bytes; 0: the gateway's default "
                       "(one Ethernet frame)")
            ->capture_default_str();
        app.add_flag("--robot-shm", robot_shm,
                     "the gateway's --robot-shm: its robot side offers shared memory too, so the publisher (shared "
                     "memory and UDP) sends each sample both ways");
        app.add_option("--log", log_file,
                       "the gateway's --log: its on-robot log, a row per sample forwarded (telemetry-gateway keeps "
                       "one by default)");
    }

    /// What the bench's header line says of the gateway.
    std::string describe() const {
        return std::string("gateway's robot side ") + (robot_shm ? "shared memory and UDP" : "UDP") +
               ", WAN coalescing " +
               (wan_coalesce_us > 0 ? "within " + std::to_string(wan_coalesce_us) + " us" : std::string("off")) +
               (log_file.empty() ? ", no on-robot log" : ", on-robot log " + log_file) +
               (wan_max_datagram_bytes > 0 ? ", WAN datagrams up to " + std::to_string(wan_max_datagram_bytes) + " B"
                                           : std::string(", WAN datagrams of one Ethernet frame"));
    }
};

/// The publisher's --volatile flag of the side-by-side benches (SideBySide::writer_qos).
inline void add_volatile_flag(CLI::App& app, bool& volatile_writer) {
    app.add_flag("--volatile", volatile_writer,
                 "volatile publisher, as a ROS 2 node's (default: Fast DDS's transient local, for which the gateway "
                 "keeps each instance's last sample for late joiners)");
}

/// The benches' link budget, 100 Gbit/s: every sample is released on arrival. (10 Gbit/s held 64 KiB samples
/// back above 19,000/s, which loopback carries.)
constexpr double UNCONSTRAINED_BUDGET_BPS = 1e11;

/// "budget 100 Gbit/s", for the benches' header lines.
inline std::string describe_unconstrained_budget() {
    return "budget " + std::to_string(static_cast<long long>(UNCONSTRAINED_BUDGET_BPS / 1e9)) + " Gbit/s";
}

/// The gateway of the benches: budget unconstrained, the direct topics denied.
inline tgw::dds::GatewayConfig gateway_config(const BenchDomains& d, const GatewayOptions& options = {}) {
    tgw::dds::GatewayConfig config;
    config.robot_domain = d.robot;
    config.wan_domain = d.wan;
    config.wan_peers = {"127.0.0.1:" + std::to_string(d.wan_reader_port)};
    config.wan_interface = "127.0.0.1";
    config.wan_port = d.gateway_wan_port;
    config.deny = {"bench/direct/*"};
    config.scheduler.initial_rate_bps = UNCONSTRAINED_BUDGET_BPS;
    config.default_ttl = std::chrono::seconds(5);
    if (options.wan_max_datagram_bytes > 0) {
        config.scheduler.wire = tgw::core::WireModel::for_max_datagram(options.wan_max_datagram_bytes);
    }
    config.robot.shm = options.robot_shm;
    config.wan_coalesce_window = std::chrono::microseconds(options.wan_coalesce_us);
    config.log_file = options.log_file;
    return config;
}

/// Counts the samples it takes and, optionally, keeps their one-way latencies (receive wall time minus
/// source timestamp). Safe to share between readers.
class CountingReader final : public fdds::DataReaderListener {
  public:
    explicit CountingReader(bool keep_latencies = false) : keep_latencies_(keep_latencies) {}

    void on_data_available(fdds::DataReader* reader) override {
        tgw::idl::PaperMessage data;
        fdds::SampleInfo info;
        while (reader->take_next_sample(&data, &info) == ReturnCode_t::RETCODE_OK) {
            if (!info.valid_data) {
                continue;
            }
            received_.fetch_add(1);
            static thread_local const pid_t this_thread = ::gettid();
            listener_thread_.store(this_thread, std::memory_order_relaxed);
            if (!keep_latencies_) {
                continue;
            }
            const auto received = tgw::base::WallClock::now();
            const auto source = tgw::passthrough::to_wall_time(info.source_timestamp);
            if (source) {
                std::lock_guard<std::mutex> lock(mutex_);
                latencies_ns_.push_back(
                    std::chrono::duration_cast<std::chrono::nanoseconds>(received - *source).count());
            }
        }
    }
    void on_subscription_matched(fdds::DataReader*, const fdds::SubscriptionMatchedStatus& info) override {
        if (info.current_count_change > 0) {
            matched.fetch_add(1);
        }
    }

    std::uint64_t received() const { return received_.load(); }
    /// The thread that took the last sample (Fast DDS's receive thread for the reader's socket); 0 before any.
    pid_t listener_thread() const { return listener_thread_.load(std::memory_order_relaxed); }
    std::vector<std::int64_t> latencies_ns() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return latencies_ns_;
    }
    void clear_latencies() {
        std::lock_guard<std::mutex> lock(mutex_);
        latencies_ns_.clear();
    }

    std::atomic<int> matched{0};

  private:
    const bool keep_latencies_;
    std::atomic<std::uint64_t> received_{0};
    std::atomic<pid_t> listener_thread_{0};
    mutable std::mutex mutex_;
    std::vector<std::int64_t> latencies_ns_;
};

/// Waits until `received` has not changed for `quiet`.
template <typename F>
void settle(F received, std::chrono::milliseconds quiet = std::chrono::milliseconds(200)) {
    std::uint64_t seen = received();
    while (true) {
        std::this_thread::sleep_for(quiet);
        const std::uint64_t now = received();
        if (now == seen) {
            return;
        }
        seen = now;
    }
}

inline double percentile_us(std::vector<std::int64_t> v, double q) {
    if (v.empty()) {
        return 0.0;
    }
    std::sort(v.begin(), v.end());
    const auto rank = static_cast<std::size_t>(std::max(1.0, std::ceil(q * static_cast<double>(v.size()))));
    return static_cast<double>(v[std::min(rank, v.size()) - 1]) / 1e3;
}

}  // namespace tgw::bench
