#include "basecamp/cli/linkmap_command.hpp"

#include <filesystem>
#include <iostream>
#include <memory>

#include "basecamp/analysis/link_map.hpp"
#include "basecamp/analysis/link_map_render.hpp"
#include "basecamp/recording/recording_reader.hpp"

namespace tgw::basecamp {

namespace {

struct LinkmapOptions {
    std::vector<std::string> files;
    std::string pose = "robot/pose";
    std::string out;
    std::vector<std::string> idl_dirs;
};

int run_linkmap(const LinkmapOptions& options) {
    const PoseSource pose = PoseSource::parse(options.pose, "--pose");
    std::vector<std::unique_ptr<RecordingReader>> recordings;
    std::string names;
    for (const std::string& file : options.files) {
        recordings.push_back(std::make_unique<RecordingReader>(file, "FILE"));
        names += (names.empty() ? "" : " + ") + std::filesystem::path(file).filename().string();
    }
    LinkMapBuilder builder(pose, types::TypeLibrary::project_and(options.idl_dirs, "--idl"));
    for (const auto& recording : recordings) {
        recording->read(builder);
        for (const auto& [time_ns, rate_bps] : recording->link_rates())
            builder.add_logged_rate(time_ns, rate_bps);
    }
    const LinkMap map = builder.build("--pose", names);
    render_link_map(map, "Link rate along the robot's path: " + names, options.out, "--out");
    std::cout << "tm-basecamp linkmap: " << map.poses << " poses of " << pose.topic << ", " << map.rate_points
              << " rates from " << map.rates_from << " (" << map.min_rate_bps / 1000 << " to "
              << map.max_rate_bps / 1000 << " kbit/s), " << map.dropped_samples << " samples dropped on the robot at "
              << map.drops.size() << " places (from " << map.drops_from << ") -> " << options.out << "\n";
    return 0;
}

}  // namespace

Subcommand add_linkmap_command(CLI::App& app) {
    auto options = std::make_shared<LinkmapOptions>();
    CLI::App* command = app.add_subcommand(
        "linkmap", "draw the robot's path coloured by the link's rate, and where samples stayed on the robot (PNG)");
    command
        ->add_option("FILE", options->files,
                     "recordings with the pose topic and tgw/status, and a mission archive of 'merge' for the drops "
                     "sample by sample (its statuses are left out: give the recording too)")
        ->required()
        ->check(CLI::ExistingFile);
    command
        ->add_option("--pose", options->pose,
                     "the pose topic, and which members are x and y (default x,y; a.b.c for nested members)")
        ->capture_default_str();
    command->add_option("--out", options->out, "the PNG file to write")->required();
    add_idl_option(*command, options->idl_dirs);
    return {command, [options] { return run_linkmap(*options); }};
}

}  // namespace tgw::basecamp
