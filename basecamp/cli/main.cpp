// tm-basecamp: the base camp's side of the link. record: every topic of a domain into SQLite; relay: every topic
// of the WAN domain into the camp's own domain; report: the paper's metrics per topic from a recording, and with
// the gateway's on-robot log where every missing sample went.
#include <CLI/CLI.hpp>

#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "base/config_error.hpp"
#include "base/config_file.hpp"
#include "base/fastdds_log_reporter.hpp"
#include "basecamp/cli/echo_command.hpp"
#include "basecamp/cli/export_command.hpp"
#include "basecamp/cli/linkmap_command.hpp"
#include "basecamp/cli/merge_command.hpp"
#include "basecamp/cli/record_command.hpp"
#include "basecamp/cli/relay_command.hpp"
#include "basecamp/cli/report_command.hpp"
#include "basecamp/cli/stats_command.hpp"
#include "basecamp/cli/status_command.hpp"
#include "basecamp/cli/subcommand.hpp"

int main(int argc, char** argv) {
    tgw::base::report_fastdds_log_as("tm-basecamp");
    CLI::App app{"tm-basecamp: records every topic of the WAN domain and reports on-time delivery per topic"};
    app.set_version_flag("--version", std::string("tm-basecamp ") + TGW_VERSION);
    app.require_subcommand(1);

    // In the order `tm-basecamp --help` lists them.
    const std::vector<tgw::basecamp::Subcommand> subcommands = {
        tgw::basecamp::add_record_command(app),  tgw::basecamp::add_report_command(app),
        tgw::basecamp::add_echo_command(app),    tgw::basecamp::add_export_command(app),
        tgw::basecamp::add_linkmap_command(app), tgw::basecamp::add_merge_command(app),
        tgw::basecamp::add_relay_command(app),   tgw::basecamp::add_stats_command(app),
        tgw::basecamp::add_status_command(app),
    };

    std::vector<tgw::base::ConfigFile*> config_files;
    for (const tgw::basecamp::Subcommand& subcommand : subcommands) {
        if (subcommand.config)
            config_files.push_back(subcommand.config.get());
    }
    if (const std::optional<int> exit_code = tgw::base::read_command_line(app, argc, argv, config_files))
        return *exit_code;

    try {
        for (const tgw::basecamp::Subcommand& subcommand : subcommands) {
            if (subcommand.command->parsed())
                return subcommand.run();
        }
    } catch (const tgw::base::ConfigError& e) {
        // A flag's value from a file is told at its key there.
        std::cerr << "tm-basecamp: " << tgw::base::explain_config_error(e.what(), config_files) << "\n";
        return 2;
    }
    return 0;
}
