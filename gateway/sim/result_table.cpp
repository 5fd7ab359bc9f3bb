#include "gateway/sim/result_table.hpp"

#include <cstdio>
#include <sstream>
#include <utility>

namespace tgw::sim {

namespace {
std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0) {
    char buf[64];
    std::snprintf(buf, sizeof buf, fmt, a, b, c);
    return buf;
}
}  // namespace

ResultTable::ResultTable(std::vector<core::MessageStream> workload, core::PolicyKind policy, double duration_s)
    : workload_(std::move(workload)), policy_(policy), duration_s_(duration_s) {}

double ResultTable::on_time_payload_bits(const SimulationResult& result) const {
    double bits = 0.0;
    for (std::size_t i = 0; i < workload_.size(); ++i) {
        bits += 8.0 * static_cast<double>(result.per_stream[i].on_time) *
                static_cast<double>(core::paper_message_serialized_bytes(workload_[i].data_bytes));
    }
    return bits;
}

void ResultTable::add(std::string link_name, SimulationResult result) {
    rows_.emplace_back(std::move(link_name), std::move(result));
}

std::string ResultTable::detailed_markdown() const {
    std::ostringstream out;
    for (const auto& [link, result] : rows_) {
        out << "policy " << core::to_string(policy_) << ", link " << link << ", " << duration_s_
            << " s of publishing\n\n";
        out << "| type | TTL s | offered | on time | % on time | late | lost on link |";
        for (auto name : core::DROP_REASON_NAMES)
            out << ' ' << name << " |";
        out << " mean s | sd s |\n|---|---|---|---|---|---|---|";
        for (std::size_t i = 0; i < core::DROP_REASON_COUNT; ++i)
            out << "---|";
        out << "---|---|\n";
        for (std::size_t i = 0; i < workload_.size(); ++i) {
            const DeliveryStats& s = result.per_stream[i];
            out << "| " << workload_[i].type << " | " << base::to_seconds(workload_[i].ttl) << " | " << s.offered
                << " | " << s.on_time << " | " << format("%.1f", s.on_time_percent()) << " | " << s.late << " | "
                << s.lost_on_link << " |";
            for (auto n : s.logged)
                out << ' ' << n << " |";
            out << ' ' << format("%.3f", s.mean_s()) << " | " << format("%.3f", s.stddev_s()) << " |\n";
        }
        out << "\nlink: " << result.link_sent_bits / 8 << " bytes sent, " << result.link_dropped_bits / 8
            << " bytes dropped by the shaper\n";
        out << "on-time payload: " << format("%.0f", on_time_payload_bits(result) / duration_s_)
            << " bit/s of serialized samples, "
            << format("%.1f", 100.0 * on_time_payload_bits(result) / result.measured_capacity_bits)
            << " % of what the link could carry\n\n";
    }
    return out.str();
}

std::string ResultTable::summary_markdown() const {
    std::ostringstream out;
    out << "policy " << core::to_string(policy_) << ": percent on time (mean transmission time in s)\n\n| link |";
    for (const auto& w : workload_)
        out << ' ' << w.type << " |";
    out << "\n|---|";
    for (std::size_t i = 0; i < workload_.size(); ++i)
        out << "---|";
    out << '\n';
    for (const auto& [link, result] : rows_) {
        out << "| " << link << " |";
        for (const DeliveryStats& s : result.per_stream) {
            out << ' ' << format("%.1f (%.2f)", s.on_time_percent(), s.mean_s()) << " |";
        }
        out << '\n';
    }
    return out.str();
}

}  // namespace tgw::sim
