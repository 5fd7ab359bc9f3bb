#include "basecamp/cli/merge_command.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "basecamp/analysis/mission_archive.hpp"

namespace tgw::basecamp {

namespace {

/// Exit code after SIGINT or SIGTERM, as a shell reports a program that the signal ended.
constexpr int EXIT_INTERRUPTED = 130;

struct MergeOptions {
    std::string robot_log;
    std::string recording;
    std::string out;
};

std::string count_or_dash(const std::optional<std::uint64_t>& n) {
    return n ? std::to_string(*n) : std::string("-");
}

void print_row(std::ostream& out, int topic_width, const TopicFates& t) {
    char line[512];
    int used = std::snprintf(line, sizeof(line), "%-*s %9llu %9llu %9s %9llu", topic_width, t.topic.c_str(),
                             static_cast<unsigned long long>(t.produced()), static_cast<unsigned long long>(t.received),
                             count_or_dash(t.on_time).c_str(), static_cast<unsigned long long>(t.dropped_total()));
    for (const std::uint64_t n : t.dropped)
        used += std::snprintf(line + used, sizeof(line) - static_cast<std::size_t>(used), " %12llu",
                              static_cast<unsigned long long>(n));
    std::snprintf(line + used, sizeof(line) - static_cast<std::size_t>(used), " %9llu %10llu\n",
                  static_cast<unsigned long long>(t.lost), static_cast<unsigned long long>(t.backfilled));
    out << line;
}

void print_counts(std::ostream& out, const std::string& archive, const MergeCounts& counts) {
    out << "tm-basecamp merge: " << counts.total.produced() << " samples -> " << archive << "\n";
    int topic_width = 20;
    for (const TopicFates& t : counts.topics)
        topic_width = std::max(topic_width, static_cast<int>(t.topic.size()));
    char line[512];
    int used = std::snprintf(line, sizeof(line), "%-*s %9s %9s %9s %9s", topic_width, "topic", "produced", "received",
                             "on_time", "dropped");
    for (const std::string_view reason : core::DROP_REASON_NAMES)
        used += std::snprintf(line + used, sizeof(line) - static_cast<std::size_t>(used), " %12.*s",
                              static_cast<int>(reason.size()), reason.data());
    std::snprintf(line + used, sizeof(line) - static_cast<std::size_t>(used), " %9s %10s\n", "lost", "backfilled");
    out << line;
    for (const TopicFates& t : counts.topics)
        print_row(out, topic_width, t);
    print_row(out, topic_width, counts.total);
    out << "on time: receive - source time <= the recording's Lifespan (the gateway's TTL); '-': none known.\n"
           "lost: written to the WAN by the gateway, never recorded at the base camp.\n";
    if (counts.total.backfilled > 0)
        out << "backfilled: of the dropped, in the camp's recording by backfill (" << counts.total.backfilled << " of "
            << counts.total.dropped_total() << "); " << counts.total.dropped_total() - counts.total.backfilled
            << " only on the robot.\n";
    if (counts.total.received_unmatched > 0)
        out << counts.total.received_unmatched
            << " received sample(s) match no row of the on-robot log (recorded outside the log's time, or rows the "
               "log could not write): kept as received, their robot columns NULL.\n";
    if (counts.total.dropped_other > 0)
        out << counts.total.dropped_other
            << " dropped sample(s) with a reason this build does not know: in 'dropped', in no reason's column.\n";
}

}  // namespace

Subcommand add_merge_command(CLI::App& app) {
    auto options = std::make_shared<MergeOptions>();
    CLI::App* merge = app.add_subcommand(
        "merge", "the full mission archive: every sample the robot produced, once, received, dropped or lost");
    merge->add_option("ROBOT_LOG", options->robot_log, "the gateway's on-robot log (telemetry-gateway --log)")
        ->required();
    merge->add_option("RECORDING", options->recording, "the base camp's recording (tm-basecamp record|relay --out)")
        ->required();
    merge
        ->add_option("--out", options->out,
                     "the archive to write (SQLite); an existing archive is replaced once the new one is whole")
        ->required();
    return {merge, [options] {
                stop_on_signals();
                const auto counts =
                    merge_mission(options->robot_log, options->recording, options->out, &stop_requested());
                if (!counts) {
                    std::cerr << "tm-basecamp merge: interrupted; " << options->out << " unchanged\n";
                    return EXIT_INTERRUPTED;
                }
                print_counts(std::cout, options->out, *counts);
                return 0;
            }};
}

}  // namespace tgw::basecamp
