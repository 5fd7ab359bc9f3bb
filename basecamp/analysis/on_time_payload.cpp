#include "basecamp/analysis/on_time_payload.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>

#include "base/config_error.hpp"
#include "base/sqlite_handles.hpp"
#include "basecamp/recording/read_only_db.hpp"
#include "wire/gateway_topics.hpp"

namespace tgw::basecamp {

namespace {

struct Arrival {
    std::int64_t source_ns;
    std::int64_t receive_ns;
    std::int64_t ttl_ns;
    std::uint64_t bytes;
};

}  // namespace

std::optional<OnTimePayload> read_on_time_payload(const std::string& path, const std::vector<TopicReport>& reports,
                                                  std::int64_t since_ns, double link_rate_bps) {
    std::map<std::string, std::int64_t> ttl_ns;
    for (const TopicReport& r : reports) {
        if (r.ttl_s && !wire::is_gateway_topic(r.topic)) {
            ttl_ns[r.topic] = static_cast<std::int64_t>(*r.ttl_s * 1e9);
        }
    }
    const base::DbPtr db = open_read_only(path, "report");
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db.get(),
                           "SELECT topic, source_ns, receive_ns, length(payload) FROM samples WHERE source_ns >= ?1",
                           -1, &stmt, nullptr) != SQLITE_OK) {
        throw base::ConfigError(path + ": not a tm-basecamp recording: " + sqlite3_errmsg(db.get()));
    }
    const base::StmtPtr rows(stmt);
    sqlite3_bind_int64(rows.get(), 1, since_ns);

    std::vector<Arrival> arrivals;
    std::int64_t first_source = std::numeric_limits<std::int64_t>::max();
    std::int64_t last_source = std::numeric_limits<std::int64_t>::min();
    while (sqlite3_step(rows.get()) == SQLITE_ROW) {
        const auto it = ttl_ns.find(reinterpret_cast<const char*>(sqlite3_column_text(rows.get(), 0)));
        if (it == ttl_ns.end()) {
            continue;
        }
        const Arrival a{sqlite3_column_int64(rows.get(), 1), sqlite3_column_int64(rows.get(), 2), it->second,
                        static_cast<std::uint64_t>(sqlite3_column_int64(rows.get(), 3))};
        first_source = std::min(first_source, a.source_ns);
        last_source = std::max(last_source, a.source_ns);
        arrivals.push_back(a);
    }
    if (arrivals.empty()) {
        return std::nullopt;
    }
    const auto from_ns = static_cast<std::int64_t>(OnTimePayload::STEADY_START_S * 1e9);
    const auto margin_ns = static_cast<std::int64_t>(OnTimePayload::STEADY_END_MARGIN_S * 1e9);
    const std::int64_t begin = first_source + from_ns;
    const std::int64_t end = last_source - margin_ns;
    if (end <= begin) {
        return std::nullopt;
    }
    OnTimePayload out;
    out.window_start_s = OnTimePayload::STEADY_START_S;
    out.window_end_s = static_cast<double>(end - first_source) / 1e9;
    out.link_rate_bps = link_rate_bps;
    for (const Arrival& a : arrivals) {
        if (a.receive_ns >= begin && a.receive_ns < end && a.receive_ns - a.source_ns <= a.ttl_ns) {
            ++out.samples;
            out.bytes += a.bytes;
        }
    }
    out.bits_per_s = 8.0 * static_cast<double>(out.bytes) / (static_cast<double>(end - begin) / 1e9);
    return out;
}

void print_on_time_payload(std::ostream& out, const std::optional<OnTimePayload>& payload, double link_rate_bps) {
    char line[400];
    if (!payload) {
        std::snprintf(line, sizeof(line),
                      "on-time payload: none computed: the recording's samples with a TTL span less than %.0f s of "
                      "source time\n",
                      OnTimePayload::STEADY_START_S + OnTimePayload::STEADY_END_MARGIN_S);
        out << line;
        return;
    }
    std::snprintf(line, sizeof(line),
                  "on-time payload: %.0f bit/s, %.1f %% of %.0f bit/s (%llu samples, %llu serialized bytes, that "
                  "arrived within their TTL from %.0f to %.1f s after the first source time)\n",
                  payload->bits_per_s, payload->percent_of_link(), link_rate_bps,
                  static_cast<unsigned long long>(payload->samples), static_cast<unsigned long long>(payload->bytes),
                  payload->window_start_s, payload->window_end_s);
    out << line;
}

}  // namespace tgw::basecamp
