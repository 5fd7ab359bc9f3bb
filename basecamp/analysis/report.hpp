#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "basecamp/analysis/drop_accounting.hpp"

namespace tgw::basecamp {

/// What `tm-basecamp report` computes for one topic: the paper's two metrics.
struct TopicReport {
    std::string topic;
    std::string robot;  ///< whose gateway bridges it, per the gateways' status recorded; empty when unnamed or unknown
    std::string type_name;
    std::optional<double> ttl_s;  ///< from --ttl, else the writer's declared Lifespan; empty if neither
    std::string ttl_from;         ///< "flag", "profile", "lifespan" or "" when unknown
    std::uint64_t received = 0;
    std::uint64_t on_time = 0;             ///< received with transmission time <= TTL
    std::optional<std::uint64_t> offered;  ///< samples published, when known
    std::string offered_from;              ///< "flag" or "sequence" (PaperMessage sequence numbers)
    double mean_ms = 0.0;                  ///< transmission time: receive minus source timestamp
    double stddev_ms = 0.0;                ///< sample standard deviation
    double max_ms = 0.0;
    std::optional<DropAccounting> accounting;  ///< with --robot-log: where every sample not received went
    /// Samples that missed their TTL and reached the recording later, backfilled from the on-robot log: in none of
    /// the figures above (they were not delivered live).
    std::uint64_t backfilled = 0;
};

struct ReportOptions {
    std::map<std::string, double> ttl_s;  ///< --ttl TOPIC=S
    /// --qos FILE: the TTL of a topic from its data_writer profile, consulted after --ttl and before the
    /// writer's recorded Lifespan; empty without --qos.
    std::function<std::optional<double>(const std::string& topic)> profile_ttl_s;
    std::map<std::string, std::uint64_t> offered;    ///< --offered TOPIC=N
    std::string robot_log;                           ///< --robot-log FILE: the gateway's on-robot log
    std::map<std::string, std::uint64_t> forwarded;  ///< --forwarded TOPIC=N: samples the gateway wrote to the WAN
    std::int64_t since_ns =
        std::numeric_limits<std::int64_t>::min();  ///< --since-ns: ignore samples with an earlier source time
};

/// Reads a recording made by `tm-basecamp record` (and, with `robot_log`, the gateway's on-robot log). Throws
/// base::ConfigError naming the file if it cannot.
std::vector<TopicReport> read_report(const std::string& path, const ReportOptions& options);

/// The per-topic table, and the accounting table when the reports have one.
void print_report(std::ostream& out, const std::vector<TopicReport>& reports);

}  // namespace tgw::basecamp
