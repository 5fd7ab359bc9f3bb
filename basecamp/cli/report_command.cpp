#include "basecamp/cli/report_command.hpp"

#include <exception>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/config_error.hpp"
#include "base/time.hpp"
#include "basecamp/analysis/grant_summary.hpp"
#include "basecamp/analysis/on_time_payload.hpp"
#include "basecamp/analysis/report.hpp"
#include "passthrough/qos_file.hpp"

namespace tgw::basecamp {

namespace {

struct ReportCommandOptions {
    std::string in;
    std::vector<std::string> ttls;
    std::string qos_file;
    std::vector<std::string> offered;
    std::string robot_log;
    std::vector<std::string> forwarded;
    long long since_ns = 0;
    CLI::Option* since = nullptr;
    double link_rate_bps = 0.0;
    CLI::Option* link_rate = nullptr;
};

/// Splits "TOPIC=VALUE" at its last '='; topics may contain '='-free slashes and colons.
template <typename T>
std::map<std::string, T> parse_assignments(const std::vector<std::string>& items, const std::string& flag) {
    std::map<std::string, T> result;
    for (const std::string& item : items) {
        const auto eq = item.rfind('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == item.size())
            throw base::ConfigError(flag + ": expected TOPIC=VALUE, got '" + item + "'");
        try {
            std::size_t used = 0;
            const std::string value = item.substr(eq + 1);
            const double number = std::stod(value, &used);
            if (used != value.size() || number < 0)
                throw std::invalid_argument(value);
            result[item.substr(0, eq)] = static_cast<T>(number);
        } catch (const std::exception&) {
            throw base::ConfigError(flag + ": '" + item + "': the value is not a non-negative number");
        }
    }
    return result;
}

int run_report(const ReportCommandOptions& command) {
    ReportOptions options;
    options.ttl_s = parse_assignments<double>(command.ttls, "--ttl");
    if (!command.qos_file.empty()) {
        passthrough::load_qos_file(command.qos_file);
        options.profile_ttl_s = [](const std::string& topic) -> std::optional<double> {
            const auto lifespan = passthrough::writer_profile_lifespan(topic);
            return lifespan ? std::optional<double>(base::to_seconds(*lifespan)) : std::nullopt;
        };
    }
    options.offered = parse_assignments<std::uint64_t>(command.offered, "--offered");
    options.forwarded = parse_assignments<std::uint64_t>(command.forwarded, "--forwarded");
    options.robot_log = command.robot_log;
    if (command.since->count() > 0)
        options.since_ns = command.since_ns;
    if (!options.forwarded.empty() && command.robot_log.empty())
        throw base::ConfigError("--forwarded: needs --robot-log");
    if (command.link_rate->count() > 0 && !(command.link_rate_bps > 0.0))
        throw base::ConfigError("--link-rate " + command.link_rate->as<std::string>() + ": expected bit/s above 0");
    const std::vector<TopicReport> reports = read_report(command.in, options);
    print_report(std::cout, reports);
    if (const auto grants = read_grant_summary(command.in))
        print_grant_summary(std::cout, *grants);
    if (command.link_rate_bps > 0.0) {
        print_on_time_payload(std::cout,
                              read_on_time_payload(command.in, reports, options.since_ns, command.link_rate_bps),
                              command.link_rate_bps);
    }
    return 0;
}

}  // namespace

Subcommand add_report_command(CLI::App& app) {
    auto options = std::make_shared<ReportCommandOptions>();
    CLI::App* command = app.add_subcommand("report", "print received, on time and transmission time per topic");
    command->add_option("FILE", options->in, "a recording made by 'tm-basecamp record'")
        ->required()
        ->check(CLI::ExistingFile);
    command->add_option("--ttl", options->ttls,
                        "TOPIC=SECONDS: the TTL to judge a topic by (default: the writer's Lifespan)");
    command->add_option("--qos", options->qos_file,
                        "Fast DDS XML: a data_writer profile named after a topic gives its TTL (after --ttl, before "
                        "the writer's Lifespan)");
    command->add_option("--offered", options->offered, "TOPIC=N: how many samples the robot published on a topic");
    command
        ->add_option("--robot-log", options->robot_log,
                     "the gateway's on-robot log (telemetry-gateway --log): account for every sample not received")
        ->check(CLI::ExistingFile);
    command->add_option("--forwarded", options->forwarded,
                        "TOPIC=N: how many samples the gateway wrote to the WAN (makes lost on the link exact)");
    options->since =
        command->add_option("--since-ns", options->since_ns,
                            "ignore samples (recording and log) with a source time before this, ns since the epoch");
    options->link_rate =
        command->add_option("--link-rate", options->link_rate_bps,
                            "bit/s: also print the on-time payload, the serialized bytes that arrived within their "
                            "TTL over the steady window, as a share of this rate");
    return {command, [options] { return run_report(*options); }};
}

}  // namespace tgw::basecamp
