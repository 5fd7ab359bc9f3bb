#include "basecamp/cli/export_command.hpp"

#include <iostream>
#include <memory>

#include "basecamp/recording/mcap_recording.hpp"
#include "basecamp/recording/recording_reader.hpp"

namespace tgw::basecamp {

namespace {

struct ExportOptions {
    std::string recording;
    McapOptions mcap;
};

int run_export(const ExportOptions& options) {
    RecordingReader recording(options.recording, "FILE");
    McapRecording mcap(options.mcap.path, "--mcap", types::TypeLibrary::project_and(options.mcap.idl_dirs, "--idl"),
                       parse_mcap_compression(options.mcap.compression, "--compression"), options.mcap.chunk_bytes);
    const std::uint64_t samples = recording.read(mcap);
    if (!mcap.close()) {
        std::cerr << "tm-basecamp export: writing '" << options.mcap.path << "' failed\n";
        return 1;
    }
    std::cout << "tm-basecamp export: " << samples << " samples of " << options.recording << " -> " << options.mcap.path
              << " (" << options.mcap.compression << ")\n";
    if (mcap.channels_without_schema() > 0)
        std::cout << "  " << mcap.channels_without_schema()
                  << " topic(s) without schema: no IDL for their type (--idl DIR adds IDL files)\n";
    return 0;
}

}  // namespace

Subcommand add_export_command(CLI::App& app) {
    auto options = std::make_shared<ExportOptions>();
    CLI::App* command =
        app.add_subcommand("export", "write a recording or mission archive as an MCAP file (Foxglove, rosbag2, mcap)");
    command
        ->add_option("FILE", options->recording,
                     "a recording of 'tm-basecamp record' or 'relay --out', or a mission archive of 'merge' (what "
                     "stayed on the robot goes on channels dropped/REASON/TOPIC and lost/TOPIC)")
        ->required()
        ->check(CLI::ExistingFile);
    add_mcap_options(*command, options->mcap, true);
    return {command, [options] { return run_export(*options); }};
}

}  // namespace tgw::basecamp
