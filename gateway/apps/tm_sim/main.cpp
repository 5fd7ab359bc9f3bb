// tm-sim: the scheduling core alone, in simulated time, on the paper workload.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "base/cli_checks.hpp"
#include "base/config_error.hpp"
#include "gateway/sim/result_table.hpp"
#include "gateway/sim/simulation.hpp"
#include "sensor/rate_trace.hpp"

namespace {

using tgw::base::ConfigError;
using tgw::core::PolicyKind;

std::vector<PolicyKind> parse_policies(const std::vector<std::string>& names) {
    std::vector<PolicyKind> policies;
    for (const std::string& name : names) {
        if (name == "all") {
            return {PolicyKind::ttl, PolicyKind::edf, PolicyKind::paper, PolicyKind::fifo};
        }
        const auto p = tgw::core::parse_policy(name);
        if (!p)
            throw ConfigError("--policy: unknown policy '" + name + "' (ttl, edf, paper, fifo or all)");
        policies.push_back(*p);
    }
    return policies;
}

tgw::sim::RateProfile load_trace_profile(const std::string& file) {
    return tgw::sim::RateProfile(tgw::sensor::load_rate_trace(file));
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"tm-sim: the telemetry scheduler alone in simulated time, on the paper's workload"};
    app.set_version_flag("--version", std::string("tm-sim ") + TGW_VERSION);
    std::vector<std::string> policy_names{"ttl"};
    std::string workload = "paper";
    std::vector<double> rates;
    std::string trace_file;
    double duration_s = 60.0;
    double warmup_s = 0.0;
    double link_queue_ms = 1000.0;
    std::uint64_t link_burst_bytes = tgw::sim::SimulationConfig{}.link_burst_bytes;
    double overhead_factor = 1.0;
    double paper_period_s = 1.0;
    double paper_overhead = 0.0;
    double budget_fraction = tgw::core::SchedulerConfig{}.budget_fraction;
    bool summary = false;
    std::string wan_mode = "standard";
    app.add_option("--wan-mode", wan_mode,
                   "standard: a DDS sample per sample; compact: what leaves together goes as one bundle")
        ->check(CLI::IsMember({"standard", "compact"}));
    app.add_option("--policy", policy_names, "ttl, edf, paper, fifo or all; repeatable")->delimiter(',');
    app.add_option("--workload", workload, "the workload: paper")->check(CLI::IsMember({"paper"}));
    app.add_option("--rate", rates, "link rate in bit/s; repeatable or comma-separated")
        ->delimiter(',')
        ->check(tgw::base::positive());
    app.add_option("--trace", trace_file, "link rate over time: lines of 'seconds bits_per_second'");
    app.add_option("--duration", duration_s, "seconds of publishing")->check(tgw::base::positive());
    app.add_option("--warmup", warmup_s, "seconds of publishing before the measured window (steady state)")
        ->check(tgw::base::non_negative());
    app.add_option("--link-queue-ms", link_queue_ms,
                   "the shaper's queue depth (tbf latency): it holds rate/8 * this + the burst in bytes")
        ->check(tgw::base::non_negative());
    app.add_option("--link-burst", link_burst_bytes, "the shaper's token bucket in bytes (tbf burst)")
        ->check(tgw::base::positive())
        ->capture_default_str();
    app.add_option("--overhead-factor", overhead_factor,
                   "true wire cost over the gateway's wire model (1 = perfectly calibrated)")
        ->check(tgw::base::positive());
    app.add_option("--paper-period", paper_period_s, "paper policy: the filter's period in seconds")
        ->check(tgw::base::positive());
    app.add_option("--paper-overhead", paper_overhead, "paper policy: assumed overhead, 0.25 = 25 %")
        ->check(tgw::base::non_negative());
    CLI::Option* budget_fraction_option =
        app.add_option("--budget-fraction", budget_fraction,
                       "share of the sensed rate the scheduler spends (default: 0.95, in --wan-mode compact 0.99)")
            ->check(tgw::base::number_in(0.01, 1.0, "a fraction from 0.01 to 1", "IN [0.01, 1]"));
    app.add_flag("--summary", summary, "one Markdown row per rate: percent on time per type");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }

    try {
        const std::vector<PolicyKind> policies = parse_policies(policy_names);
        const bool compact = wan_mode == "compact";
        if (compact && budget_fraction_option->count() == 0) {
            budget_fraction = tgw::core::SchedulerConfig::COMPACT_BUDGET_FRACTION;  // as telemetry-gateway
        }
        for (PolicyKind policy : policies) {
            if (compact && policy != PolicyKind::ttl && policy != PolicyKind::edf) {
                throw ConfigError("--wan-mode compact: bundles are for --policy ttl and edf, not " +
                                  std::string(tgw::core::to_string(policy)));
            }
        }
        if (rates.empty() == trace_file.empty()) {
            throw ConfigError("give either --rate or --trace (one of them)");
        }
        std::vector<tgw::sim::RateProfile> links;
        std::vector<std::string> link_names;
        if (!trace_file.empty()) {
            links.push_back(load_trace_profile(trace_file));
            link_names.push_back("trace " + trace_file);
        }
        for (double rate : rates) {
            links.push_back(tgw::sim::RateProfile::constant(rate));
            link_names.push_back(std::to_string(static_cast<long>(rate)) + " bit/s");
        }

        for (PolicyKind policy : policies) {
            tgw::sim::ResultTable table(tgw::core::paper_workload(), policy, duration_s);
            for (std::size_t i = 0; i < links.size(); ++i) {
                tgw::sim::SimulationConfig config;
                config.scheduler.policy = policy;
                config.scheduler.paper_period = tgw::base::from_seconds(paper_period_s);
                config.scheduler.paper_overhead = paper_overhead;
                config.scheduler.budget_fraction = budget_fraction;
                if (compact) {
                    // As telemetry-gateway --wan-mode compact: bundles, no statistics submessage, no INFO_DST, no
                    // INFO_TS.
                    config.scheduler.bundles = tgw::core::BundleLimits{};
                    config.scheduler.wire =
                        config.scheduler.wire.without_statistics().without_destination().without_timestamp();
                }
                config.link = links[i];
                config.duration = tgw::base::from_seconds(duration_s);
                config.warmup = tgw::base::from_seconds(warmup_s);
                config.link_queue_limit = tgw::base::from_seconds(link_queue_ms / 1000.0);
                config.link_burst_bytes = link_burst_bytes;
                config.true_overhead_factor = overhead_factor;
                table.add(link_names[i], tgw::sim::run_simulation(config));
            }
            std::cout << (summary ? table.summary_markdown() : table.detailed_markdown()) << '\n';
        }
    } catch (const ConfigError& e) {
        std::cerr << "tm-sim: " << e.what() << '\n';
        return 2;
    }
    return 0;
}
