#include "basecamp/live/status_view.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

#include "basecamp/status/gateway_status.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {

namespace {

/// Backfill's rate is what the camp acknowledged over this long: a few statuses on a slow link, the link's recent
/// spare capacity rather than a moment of it.
constexpr std::int64_t BACKFILL_RATE_WINDOW_NS = 30'000'000'000;

}  // namespace

StatusView::StatusView(base::Duration history)
    : history_ns_(std::chrono::duration_cast<std::chrono::nanoseconds>(history).count()) {}

void StatusView::add(SampleRecord sample) {
    if (sample.topic != wire::STATUS_TOPIC) {
        return;
    }
    std::optional<idl::GatewayStatus> status = decode_gateway_status(sample.payload);
    std::lock_guard<std::mutex> lock(mutex_);
    if (!status) {
        ++malformed_;
        return;
    }
    ++statuses_;
    const auto& prefix = status->gateway_prefix();
    Gateway& gateway = gateways_[std::vector<std::uint8_t>(prefix.begin(), prefix.end())];
    // Plotted at the gateway's own time of each status, so the graph keeps its shape whatever the link delayed.
    gateway.rates.push_back({static_cast<std::int64_t>(status->sent_ns()), status->sensed_rate_bps()});
    while (gateway.rates.size() > 1 && gateway.rates.front().at_ns < gateway.rates.back().at_ns - history_ns_) {
        gateway.rates.pop_front();
    }
    gateway.acks.push_back({static_cast<std::int64_t>(status->sent_ns()), status->backfill_acknowledged()});
    while (gateway.acks.size() > 2 && gateway.acks[1].at_ns <= gateway.acks.back().at_ns - BACKFILL_RATE_WINDOW_NS) {
        gateway.acks.pop_front();
    }
    gateway.latest = std::move(*status);
    gateway.received_ns = sample.receive_ns;
}

std::uint64_t StatusView::statuses() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return statuses_;
}

std::uint64_t StatusView::malformed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return malformed_;
}

std::string sparkline(const std::vector<std::optional<double>>& values, double max) {
    static const char* const LEVELS[] = {"▁", "▂", "▃", "▄", "▅", "▆", "▇", "█"};
    std::string line;
    for (const std::optional<double>& value : values) {
        if (!value) {
            line += ' ';
            continue;
        }
        const double share = max > 0 ? std::clamp(*value / max, 0.0, 1.0) : 0.0;
        line += LEVELS[static_cast<int>(share * 7.0 + 0.5)];
    }
    return line;
}

namespace {

std::string prefix_hex(const std::vector<std::uint8_t>& prefix) {
    std::string text;
    char byte[4];
    for (std::size_t i = 0; i < prefix.size(); ++i) {
        std::snprintf(byte, sizeof byte, i == 0 ? "%02x" : ".%02x", prefix[i]);
        text += byte;
    }
    return text;
}

}  // namespace

void StatusView::render(std::ostream& out, std::int64_t now_ns, std::size_t columns) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (gateways_.empty()) {
        out << "no gateway status yet (tgw/status)\n";
        return;
    }
    // A fleet's gateways by robot name, each robot's block where a reader looks for it.
    std::vector<std::pair<const std::vector<std::uint8_t>*, const Gateway*>> ordered;
    for (const auto& [prefix, gateway] : gateways_) {
        ordered.emplace_back(&prefix, &gateway);
    }
    std::stable_sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) {
        return a.second->latest.robot_name() < b.second->latest.robot_name();
    });
    char line[512];
    for (const auto& [prefix_ptr, gateway_ptr] : ordered) {
        const std::vector<std::uint8_t>& prefix = *prefix_ptr;
        const Gateway& gateway = *gateway_ptr;
        const idl::GatewayStatus& s = gateway.latest;
        const std::string robot = s.robot_name().empty() ? std::string() : "robot " + s.robot_name() + ", ";
        std::snprintf(line, sizeof line, "%sgateway %s: status %.0f s old, next in %.1f s; sensor %s%s%s%s\n",
                      robot.c_str(), prefix_hex(prefix).c_str(),
                      static_cast<double>(now_ns - gateway.received_ns) / 1e9, s.status_period_s(),
                      s.sensor().empty() ? "-" : s.sensor().c_str(), s.sensor_detail().empty() ? "" : " (",
                      s.sensor_detail().c_str(), s.sensor_detail().empty() ? "" : ")");
        out << line;
        char cap[64] = "";
        if (s.delivered_cap_bps() > 0) {
            std::snprintf(cap, sizeof cap, " (capped at %.0f by the delivered-rate check)", s.delivered_cap_bps());
        }
        std::snprintf(line, sizeof line,
                      "  sensed %.0f bit/s%s, budget %.0f bit/s; outside the schedule %llu B; on-robot log %llu "
                      "samples; base-camp readers %d\n",
                      s.sensed_rate_bps(), cap, s.budget_bps(),
                      static_cast<unsigned long long>(s.unscheduled_wire_bytes()),
                      static_cast<unsigned long long>(s.log_samples()), s.matched_readers());
        out << line;
        if (s.backfill_sent() > 0 || s.backfill_rows() > 0) {
            const double oldest_s =
                s.backfill_oldest_ns() > 0
                    ? static_cast<double>(static_cast<std::int64_t>(s.sent_ns()) - s.backfill_oldest_ns()) / 1e9
                    : 0.0;
            std::snprintf(line, sizeof line,
                          "  backfill: %llu rows not yet in the camp's archive (%llu B, the oldest %.0f s old); %llu "
                          "sent, %llu acknowledged\n",
                          static_cast<unsigned long long>(s.backfill_rows()),
                          static_cast<unsigned long long>(s.backfill_bytes()), oldest_s,
                          static_cast<unsigned long long>(s.backfill_sent()),
                          static_cast<unsigned long long>(s.backfill_acknowledged()));
            out << line;
            const AckPoint& first = gateway.acks.front();
            const AckPoint& last = gateway.acks.back();
            if (last.at_ns > first.at_ns && last.acknowledged > first.acknowledged) {
                const double rows_per_s = static_cast<double>(last.acknowledged - first.acknowledged) /
                                          (static_cast<double>(last.at_ns - first.at_ns) / 1e9);
                std::snprintf(line, sizeof line, "  backfill's rate: %.1f rows/s acknowledged over the last %.0f s",
                              rows_per_s, static_cast<double>(last.at_ns - first.at_ns) / 1e9);
                out << line;
                if (s.backfill_rows() > 0) {
                    std::snprintf(line, sizeof line, "; the backlog clears in about %.0f s at it",
                                  static_cast<double>(s.backfill_rows()) / rows_per_s);
                    out << line;
                }
                out << '\n';
            }
        }

        // The graph ends at the latest status: each column is the last rate reported in its slice of time.
        const std::int64_t end = gateway.rates.back().at_ns;
        const std::int64_t slice = std::max<std::int64_t>(1, history_ns_ / static_cast<std::int64_t>(columns));
        std::vector<std::optional<double>> values(columns);
        double max = 0;
        for (const RatePoint& p : gateway.rates) {
            const std::int64_t back = (end - p.at_ns) / slice;
            if (back >= 0 && back < static_cast<std::int64_t>(columns)) {
                values[columns - 1 - static_cast<std::size_t>(back)] = p.rate_bps;
            }
            max = std::max(max, p.rate_bps);
        }
        // A rate holds until the next status: fill the columns between two reports.
        for (std::size_t i = 1; i < columns; ++i) {
            if (!values[i] && values[i - 1]) {
                values[i] = values[i - 1];
            }
        }
        std::snprintf(line, sizeof line, "  sensed rate, last %.0f min (top %.0f bit/s): |", history_ns_ / 60e9, max);
        out << line << sparkline(values, max) << "|\n";

        std::snprintf(line, sizeof line, "  %-26s %6s %7s %9s %9s %9s %8s %7s %7s %8s %8s %6s %9s %6s %10s %7s\n",
                      "topic", "ttl_s", "queued", "queued_B", "received", "forwarded", "expired", "doomed", "evicted",
                      "oversize", "shutdown", "failed", "no_reader", "capped", "superseded", "readers");
        out << line;
        for (const idl::TopicStatus& t : s.topics()) {
            std::snprintf(
                line, sizeof line,
                "  %-26s %6.3g %7u %9llu %9llu %9llu %8llu %7llu %7llu %8llu %8llu %6llu %9llu %6llu %10llu %7d\n",
                t.name().c_str(), t.ttl_ms() / 1e3, t.queued_samples(),
                static_cast<unsigned long long>(t.queued_bytes()), static_cast<unsigned long long>(t.received()),
                static_cast<unsigned long long>(t.forwarded()), static_cast<unsigned long long>(t.expired()),
                static_cast<unsigned long long>(t.doomed()), static_cast<unsigned long long>(t.evicted()),
                static_cast<unsigned long long>(t.oversize()), static_cast<unsigned long long>(t.shutdown()),
                static_cast<unsigned long long>(t.write_failed()), static_cast<unsigned long long>(t.no_reader()),
                static_cast<unsigned long long>(t.rate_capped()), static_cast<unsigned long long>(t.superseded()),
                t.matched_readers());
            out << line;
        }
        out << '\n';
    }
}

}  // namespace tgw::basecamp
