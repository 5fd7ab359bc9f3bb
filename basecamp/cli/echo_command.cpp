#include "basecamp/cli/echo_command.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "base/config_error.hpp"
#include "base/peer_transport.hpp"
#include "basecamp/live/echo.hpp"
#include "types/type_library.hpp"

namespace tgw::basecamp {

namespace {

struct EchoArguments : DomainOptions {
    std::string topic;
    std::uint64_t count = 0;
    bool json = false;
    std::vector<std::string> idl_dirs;
    double timeout_s = 0.0;
};

/// CLI11's own numeric checks print their range as 309 digits; these say what is wrong in a line.
CLI::Validator at_least_one() {
    return CLI::Validator(
        [](std::string& value) -> std::string {
            std::uint64_t n = 0;
            const char* last = value.data() + value.size();
            const auto [end, status] = std::from_chars(value.data(), last, n);
            if (status != std::errc() || end != last || n == 0)
                return "expected a whole number of 1 or more, not '" + value + "'";
            return {};
        },
        "N>=1");
}

CLI::Validator positive_seconds() {
    return CLI::Validator(
        [](std::string& value) -> std::string {
            char* end = nullptr;
            const double s = std::strtod(value.c_str(), &end);
            if (value.empty() || *end != '\0' || !std::isfinite(s) || s <= 0)
                return "expected seconds above 0, not '" + value + "'";
            return {};
        },
        "S>0");
}

int run_echo(const EchoArguments& args) {
    Echo echo(args.domain, args.transport, args.topic, types::TypeLibrary::project_and(args.idl_dirs, "--idl"),
              args.json ? SamplePrinter::Format::json : SamplePrinter::Format::text, std::cout,
              security_files(args.security_dir));
    stop_on_signals();
    const base::Duration duration = args.timeout_s > 0 ? base::from_seconds(args.timeout_s) : base::Duration::max() / 2;
    const std::uint64_t printed = echo.run(args.count, duration, stop_requested());
    if (args.count > 0 && printed < args.count && !stop_requested().load()) {
        std::cerr << "tm-basecamp echo: " << printed << " of " << args.count << " samples of '" << args.topic
                  << "' within --timeout " << args.timeout_s << " s"
                  << (echo.type_name().empty()
                          ? " (no publisher of it appeared on domain " + std::to_string(args.domain) + ")"
                          : "")
                  << "\n";
        return 1;
    }
    return 0;
}

}  // namespace

Subcommand add_echo_command(CLI::App& app) {
    auto args = std::make_shared<EchoArguments>();
    CLI::App* echo = app.add_subcommand(
        "echo", "print each sample of a topic as it arrives: field by field for IDL types, else size and hex");
    echo->add_option("TOPIC", args->topic, "the topic's DDS name (a ROS 2 topic /x is rt/x)")->required();
    add_domain_options(*echo, *args);
    echo->add_option("--count", args->count, "exit after N samples")->check(at_least_one());
    echo->add_flag("--json", args->json, "one JSON object per sample and line");
    add_idl_option(*echo, args->idl_dirs);
    echo->add_option("--timeout", args->timeout_s,
                     "seconds to wait; with --count, exit 1 if fewer samples came by then")
        ->check(positive_seconds());
    return {echo, [args] { return run_echo(*args); }};
}

}  // namespace tgw::basecamp
