#include "basecamp/live/topic_stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "basecamp/status/gateway_status.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {

TopicStats::TopicStats(base::Duration window)
    : window_ns_(std::chrono::duration_cast<std::chrono::nanoseconds>(window).count()) {}

void TopicStats::add_topic(TopicRecord topic) {
    std::lock_guard<std::mutex> lock(mutex_);
    topics_[topic.topic].lifespan_ns = topic.lifespan_ns;
}

void TopicStats::add(SampleRecord sample) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (sample.topic == wire::STATUS_TOPIC) {
        take_status_nts(sample);
    }
    Topic& topic = topics_[sample.topic];
    if (topic.total == 0) {
        topic.first_receive_ns = sample.receive_ns;
    }
    ++topic.total;
    topic.window.push_back({sample.receive_ns, sample.receive_ns - sample.source_ns, sample.payload.size()});
    while (!topic.window.empty() && topic.window.front().receive_ns < sample.receive_ns - window_ns_) {
        topic.window.pop_front();
    }
}

void TopicStats::take_status_nts(const SampleRecord& sample) {
    const std::optional<idl::GatewayStatus> status = decode_gateway_status(sample.payload);
    if (!status) {
        return;
    }
    robots_.take(*status);
    const auto& prefix = status->gateway_prefix();
    std::map<std::string, RobotSide>& topics = by_gateway_[std::vector<std::uint8_t>(prefix.begin(), prefix.end())];
    for (const idl::TopicStatus& topic : status->topics()) {
        topics[topic.name()] = RobotSide{topic.ttl_ms(), logged_on_robot(topic)};
    }
}

std::vector<TopicStatsRow> TopicStats::rows(std::int64_t now_ns) const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<TopicStatsRow> out;
    for (const auto& [name, topic] : topics_) {
        TopicStatsRow row;
        row.topic = name;
        row.robot = robots_.robot_of(name);
        row.total_samples = topic.total;

        std::optional<std::uint32_t> status_ttl_ms;
        for (const auto& [gateway, topics] : by_gateway_) {
            const auto it = topics.find(name);
            if (it != topics.end()) {
                row.logged_on_robot = row.logged_on_robot.value_or(0) + it->second.logged;
                status_ttl_ms = it->second.ttl_ms;
            }
        }
        if (topic.lifespan_ns) {
            row.ttl_s = static_cast<double>(*topic.lifespan_ns) / 1e9;
        } else if (status_ttl_ms) {
            row.ttl_s = *status_ttl_ms / 1e3;
        }

        std::vector<std::int64_t> transmission_ns;
        std::uint64_t bytes = 0;
        std::int64_t first = 0;
        std::int64_t last = 0;
        for (const Received& r : topic.window) {
            if (r.receive_ns < now_ns - window_ns_ || r.receive_ns > now_ns) {
                continue;
            }
            if (transmission_ns.empty()) {
                first = r.receive_ns;
            }
            last = r.receive_ns;
            transmission_ns.push_back(r.transmission_ns);
            bytes += r.bytes;
        }
        row.window_samples = transmission_ns.size();
        if (transmission_ns.size() >= 2 && last > first) {
            row.hz = static_cast<double>(transmission_ns.size() - 1) / (static_cast<double>(last - first) / 1e9);
        }
        // Over the window, or over the time since the topic's first sample when that is shorter.
        const std::int64_t span_ns = std::min(window_ns_, now_ns - topic.first_receive_ns);
        if (span_ns > 0) {
            row.bit_per_s = 8.0 * static_cast<double>(bytes) / (static_cast<double>(span_ns) / 1e9);
        }
        if (!transmission_ns.empty()) {
            double sum = 0;
            std::size_t on_time = 0;
            for (const std::int64_t t : transmission_ns) {
                sum += static_cast<double>(t);
                if (row.ttl_s && static_cast<double>(t) <= *row.ttl_s * 1e9) {
                    ++on_time;
                }
            }
            row.mean_ms = sum / static_cast<double>(transmission_ns.size()) / 1e6;
            std::sort(transmission_ns.begin(), transmission_ns.end());
            // Nearest rank.
            const auto rank = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(transmission_ns.size())));
            row.p99_ms = static_cast<double>(transmission_ns[std::max<std::size_t>(rank, 1) - 1]) / 1e6;
            if (row.ttl_s) {
                row.on_time_pct = 100.0 * static_cast<double>(on_time) / static_cast<double>(transmission_ns.size());
            }
        }
        out.push_back(std::move(row));
    }
    return out;
}

namespace {

std::string figure(const std::optional<double>& value, const char* format) {
    if (!value) {
        return "-";
    }
    char text[32];
    std::snprintf(text, sizeof text, format, *value);
    return text;
}

}  // namespace

void print_stats_table(std::ostream& out, const std::vector<TopicStatsRow>& rows) {
    const bool fleet = has_robot_column(rows);
    char line[256];
    std::snprintf(line, sizeof line, "%-28s %8s %10s %9s %9s %6s %8s %8s %8s", "topic", "Hz", "bit/s", "mean_ms",
                  "p99_ms", "ttl_s", "%in_ttl", "logged", "total");
    out << line << (fleet ? "  robot\n" : "\n");
    for (const TopicStatsRow& r : rows) {
        const std::optional<double> logged =
            r.logged_on_robot ? std::optional<double>(static_cast<double>(*r.logged_on_robot)) : std::nullopt;
        std::snprintf(line, sizeof line, "%-28s %8.2f %10.0f %9s %9s %6s %8s %8s %8llu", r.topic.c_str(), r.hz,
                      r.bit_per_s, figure(r.mean_ms, "%.1f").c_str(), figure(r.p99_ms, "%.1f").c_str(),
                      figure(r.ttl_s, "%.3g").c_str(), figure(r.on_time_pct, "%.1f").c_str(),
                      figure(logged, "%.0f").c_str(), static_cast<unsigned long long>(r.total_samples));
        out << line << (fleet ? "  " + robot_cell(r.robot) : std::string()) << '\n';
    }
}

}  // namespace tgw::basecamp
