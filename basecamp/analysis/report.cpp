#include "basecamp/analysis/report.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "base/config_error.hpp"
#include "base/sqlite_handles.hpp"
#include "basecamp/analysis/paper_message.hpp"
#include "basecamp/recording/read_only_db.hpp"
#include "basecamp/status/gateway_status.hpp"
#include "basecamp/status/topic_robots.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {

namespace {

/// Welford's running mean and variance: one pass, no catastrophic cancellation.
struct RunningStats {
    std::uint64_t n = 0;
    double mean = 0.0;
    double m2 = 0.0;
    double max = 0.0;

    void add(double x) {
        ++n;
        const double delta = x - mean;
        mean += delta / static_cast<double>(n);
        m2 += delta * (x - mean);
        if (n == 1 || x > max)
            max = x;
    }
    double stddev() const { return n > 1 ? std::sqrt(m2 / static_cast<double>(n - 1)) : 0.0; }
};

struct Accumulator {
    TopicReport report;
    RunningStats transit_ms;
    std::optional<std::int64_t> lifespan_ns;
    std::optional<std::uint32_t> max_sequence;
    bool all_paper = true;
    std::vector<ReceivedSample> samples;
};

}  // namespace

std::vector<TopicReport> read_report(const std::string& path, const ReportOptions& options) {
    const base::DbPtr db = open_read_only(path, "report");

    std::map<std::string, Accumulator> topics;
    const std::string not_a_recording = path + ": not a tm-basecamp recording";
    base::StmtPtr declared = prepare(db.get(), "SELECT topic, type_name, lifespan_ns FROM topics", not_a_recording);
    while (sqlite3_step(declared.get()) == SQLITE_ROW) {
        Accumulator& acc = topics[reinterpret_cast<const char*>(sqlite3_column_text(declared.get(), 0))];
        acc.report.type_name = reinterpret_cast<const char*>(sqlite3_column_text(declared.get(), 1));
        if (sqlite3_column_type(declared.get(), 2) != SQLITE_NULL)
            acc.lifespan_ns = sqlite3_column_int64(declared.get(), 2);
    }

    // Recordings made before backfill have no backfilled column: every sample in them came live.
    const std::string select = std::string("SELECT topic, type_name, source_ns, receive_ns, lifespan_ns, payload, ") +
                               (has_column(db.get(), "samples", "backfilled") ? "backfilled" : "0") +
                               " FROM samples WHERE source_ns >= ?1 ORDER BY id";
    base::StmtPtr rows = prepare(db.get(), select.c_str(), not_a_recording);
    sqlite3_bind_int64(rows.get(), 1, options.since_ns);
    std::map<std::string, std::vector<double>> transits;
    TopicRobots robots;  // from the gateways' status samples among the rows
    while (sqlite3_step(rows.get()) == SQLITE_ROW) {
        const std::string topic = reinterpret_cast<const char*>(sqlite3_column_text(rows.get(), 0));
        Accumulator& acc = topics[topic];
        const std::string type_name = reinterpret_cast<const char*>(sqlite3_column_text(rows.get(), 1));
        acc.report.type_name = type_name;
        const std::int64_t source_ns = sqlite3_column_int64(rows.get(), 2);
        const std::int64_t receive_ns = sqlite3_column_int64(rows.get(), 3);
        if (sqlite3_column_type(rows.get(), 4) != SQLITE_NULL)
            acc.lifespan_ns = sqlite3_column_int64(rows.get(), 4);
        const auto* payload = static_cast<const std::uint8_t*>(sqlite3_column_blob(rows.get(), 5));
        const auto payload_size = static_cast<std::size_t>(sqlite3_column_bytes(rows.get(), 5));
        if (sqlite3_column_int(rows.get(), 6) != 0) {
            // Published, so its sequence number counts towards what was offered; not delivered live.
            ++acc.report.backfilled;
            if (type_name == PAPER_MESSAGE_TYPE) {
                const auto seq = paper_message_sequence(payload, payload_size);
                if (seq && (!acc.max_sequence || *seq > *acc.max_sequence))
                    acc.max_sequence = seq;
            }
            continue;
        }
        if (topic == wire::STATUS_TOPIC) {
            if (const auto status = decode_gateway_status(std::vector<std::uint8_t>(payload, payload + payload_size)))
                robots.take(*status);
        }
        ++acc.report.received;
        const double transit_ms = static_cast<double>(receive_ns - source_ns) / 1e6;
        acc.transit_ms.add(transit_ms);
        transits[topic].push_back(transit_ms);
        ReceivedSample received{std::nullopt, source_ns, transit_ms};
        if (type_name == PAPER_MESSAGE_TYPE) {
            const auto seq = paper_message_sequence(payload, payload_size);
            if (seq && (!acc.max_sequence || *seq > *acc.max_sequence))
                acc.max_sequence = seq;
            received.sequence = seq;
        } else {
            acc.all_paper = false;
        }
        if (!options.robot_log.empty())
            acc.samples.push_back(received);
    }

    std::map<std::string, std::vector<LoggedSample>> logged;
    if (!options.robot_log.empty()) {
        for (LoggedSample& row : read_robot_log(options.robot_log, "--robot-log", options.since_ns)) {
            std::string topic = row.topic;
            logged[topic].push_back(std::move(row));
            topics[topic];  // a topic of which nothing arrived is still reported
        }
        for (const auto& [topic, n] : options.offered)
            topics[topic];
    }

    std::vector<TopicReport> reports;
    for (auto& [topic, acc] : topics) {
        TopicReport r = acc.report;
        r.topic = topic;
        r.robot = robots.robot_of(topic);
        const std::optional<double> profile_ttl_s =
            options.profile_ttl_s ? options.profile_ttl_s(topic) : std::optional<double>{};
        if (const auto it = options.ttl_s.find(topic); it != options.ttl_s.end()) {
            r.ttl_s = it->second;
            r.ttl_from = "flag";
        } else if (profile_ttl_s) {
            r.ttl_s = *profile_ttl_s;
            r.ttl_from = "profile";
        } else if (acc.lifespan_ns) {
            r.ttl_s = static_cast<double>(*acc.lifespan_ns) / 1e9;
            r.ttl_from = "lifespan";
        }
        if (r.ttl_s) {
            const double ttl_ms = *r.ttl_s * 1e3;
            for (double t : transits[topic])
                if (t <= ttl_ms)
                    ++r.on_time;
        }
        if (const auto it = options.offered.find(topic); it != options.offered.end()) {
            r.offered = it->second;
            r.offered_from = "flag";
        } else {
            // The log's sequence numbers count too: samples after the last one received may have been dropped.
            // Plain values rather than std::optional: GCC 12 sees the optional as maybe-uninitialized here.
            bool have_max = acc.all_paper && acc.max_sequence.has_value();
            std::uint32_t max_sequence = have_max ? *acc.max_sequence : 0;
            bool log_all_paper = acc.all_paper;
            for (const LoggedSample& row : logged[topic]) {
                log_all_paper = log_all_paper && row.sequence.has_value();
                if (row.sequence && (!have_max || *row.sequence > max_sequence)) {
                    max_sequence = *row.sequence;
                    have_max = true;
                }
            }
            if (log_all_paper && have_max) {
                r.offered = std::uint64_t{max_sequence} + 1;
                r.offered_from = "sequence";
            }
        }
        r.mean_ms = acc.transit_ms.mean;
        r.stddev_ms = acc.transit_ms.stddev();
        r.max_ms = acc.transit_ms.max;
        if (!options.robot_log.empty()) {
            std::optional<std::uint64_t> forwarded;
            if (const auto it = options.forwarded.find(topic); it != options.forwarded.end())
                forwarded = it->second;
            r.accounting = account_topic(acc.samples, logged[topic], r.ttl_s, r.offered, forwarded);
        }
        reports.push_back(r);
    }
    return reports;
}

namespace {

std::string count_or_dash(const std::optional<std::uint64_t>& n) {
    return n ? std::to_string(*n) : std::string("-");
}

void print_accounting(std::ostream& out, const std::vector<TopicReport>& reports) {
    bool any = false;
    for (const TopicReport& r : reports)
        any = any || r.accounting.has_value();
    if (!any)
        return;
    char line[320];
    out << "\naccounting: where every published sample went (received; dropped by the gateway, by the reason in its "
           "on-robot log; lost on the link)\n";
    std::snprintf(line, sizeof(line), "%-20s %8s %8s %8s %8s", "topic", "offered", "received", "on_time", "late");
    out << line;
    for (auto name : core::DROP_REASON_NAMES)
        out << ' ' << std::string(9 - std::min<std::size_t>(9, name.size()), ' ') << name;
    std::snprintf(line, sizeof(line), " %9s %11s %8s\n", "lost_link", "unaccounted", "matched");
    out << line;
    bool inferred = false;
    bool other = false;
    std::uint64_t disagree = 0;
    std::uint64_t duplicates = 0;
    for (const TopicReport& r : reports) {
        if (!r.accounting)
            continue;
        const DropAccounting& a = *r.accounting;
        std::optional<std::uint64_t> late;
        if (a.on_time)
            late = a.received - *a.on_time;
        std::snprintf(line, sizeof(line), "%-20s %8s %8llu %8s %8s", r.topic.c_str(), count_or_dash(a.offered).c_str(),
                      static_cast<unsigned long long>(a.received), count_or_dash(a.on_time).c_str(),
                      count_or_dash(late).c_str());
        out << line;
        for (std::uint64_t n : a.dropped) {
            std::snprintf(line, sizeof(line), " %9llu", static_cast<unsigned long long>(n));
            out << line;
        }
        const std::string lost =
            a.lost_on_link ? std::to_string(*a.lost_on_link) + (a.lost_inferred ? "*" : "") : std::string("-");
        const std::string unaccounted = a.unaccounted ? std::to_string(*a.unaccounted) : std::string("-");
        std::snprintf(line, sizeof(line), " %9s %11s %8s\n", lost.c_str(), unaccounted.c_str(),
                      a.by_sequence ? "sequence" : "time");
        out << line;
        inferred = inferred || (a.lost_on_link && a.lost_inferred);
        other = other || a.dropped_other > 0;
        disagree += a.logged_and_received;
        duplicates += a.duplicates_received;
    }
    out << "offered = received + dropped by the gateway + lost_link + unaccounted; samples matched by PaperMessage "
           "sequence number, else by source timestamp.\n";
    if (inferred)
        out << "*: inferred: neither received nor in the on-robot log. The gateway forwards, queues or logs every "
               "sample it takes in, so these left the robot and were lost on the way (pass --forwarded TOPIC=N, "
               "the gateway's count, to make it exact).\n";
    if (other)
        out << "some log rows have a reason this build does not know; they count as unaccounted.\n";
    if (disagree > 0)
        out << "in the on-robot log and received as well (counted as received): " << disagree << "\n";
    if (duplicates > 0)
        out << "recorded more than once (counted once): " << duplicates << "\n";
}

void print_backfilled(std::ostream& out, const std::vector<TopicReport>& reports) {
    std::string counts;
    for (const TopicReport& r : reports) {
        if (r.backfilled > 0)
            counts += (counts.empty() ? "" : ", ") + r.topic + " " + std::to_string(r.backfilled);
    }
    if (!counts.empty())
        out << "backfilled (missed their TTL, reached the recording later from the on-robot log; in no figure "
               "above): "
            << counts << "\n";
}

}  // namespace

void print_report(std::ostream& out, const std::vector<TopicReport>& reports) {
    const bool fleet = has_robot_column(reports);
    char line[320];
    std::snprintf(line, sizeof(line), "%-20s %6s %8s %8s %8s %9s %10s %10s %10s", "topic", "ttl_s", "offered",
                  "received", "on_time", "%on_time", "mean_ms", "sd_ms", "max_ms");
    out << line << (fleet ? "  robot\n" : "\n");
    bool offered_from_sequence = false;
    for (const TopicReport& r : reports) {
        char ttl[16] = "-";
        char offered[24] = "-";
        char on_time[24] = "-";
        char percent[16] = "-";
        if (r.ttl_s) {
            std::snprintf(ttl, sizeof(ttl), "%.1f", *r.ttl_s);
            std::snprintf(on_time, sizeof(on_time), "%llu", static_cast<unsigned long long>(r.on_time));
        }
        if (r.offered) {
            std::snprintf(offered, sizeof(offered), "%s%llu", r.offered_from == "sequence" ? ">=" : "",
                          static_cast<unsigned long long>(*r.offered));
            offered_from_sequence = offered_from_sequence || r.offered_from == "sequence";
        }
        const std::uint64_t base = r.offered ? *r.offered : r.received;
        if (r.ttl_s && base > 0)
            std::snprintf(percent, sizeof(percent), "%.1f", 100.0 * static_cast<double>(r.on_time) / base);
        std::snprintf(line, sizeof(line), "%-20s %6s %8s %8llu %8s %9s %10.1f %10.1f %10.1f", r.topic.c_str(), ttl,
                      offered, static_cast<unsigned long long>(r.received), on_time, percent, r.mean_ms, r.stddev_ms,
                      r.max_ms);
        out << line << (fleet ? "  " + robot_cell(r.robot) : std::string()) << '\n';
    }
    out << "on time: transmission time (receive - source timestamp) <= TTL; %on_time is of offered, or of received "
           "when offered is unknown.\n";
    if (offered_from_sequence)
        out << ">=N: offered counted from PaperMessage sequence numbers (samples after the last one received are "
               "not seen); pass --offered TOPIC=N for the exact count.\n";
    print_backfilled(out, reports);
    print_accounting(out, reports);
}

}  // namespace tgw::basecamp
