// A program's flags from one YAML file (--config FILE): every flag of a command has a key, its long name in
// snake_case (--robot-domain is robot_domain); a flag on the command line wins over the file; --print-config prints
// the configuration in force as a file that, given back, does the same (docs/configuration.md).
//
// CLI11 2.1 reads no configuration for a subcommand (tm-basecamp relay), so the file's keys become the flags they
// name, put in front of the command's own: CLI11 then checks and converts them as it does typed flags, and an error
// it finds in one is told with the file, line, column and key.
#pragma once

#include <yaml-cpp/yaml.h>
#include <CLI/CLI.hpp>

#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace tgw::base {

/// Where a key is in a configuration file, 1-based as editors count.
struct ConfigPlace {
    std::string file;
    int line = 0;
    int column = 0;

    /// "FILE:LINE:COLUMN"
    std::string text() const;
    /// Where `mark` (a node's, yaml-cpp's 0-based) is in `file`.
    static ConfigPlace at(const std::string& file, const YAML::Mark& mark);
};

class ConfigFile {
  public:
    /// Adds --config FILE and --print-config to `command` (the app itself, or one of its subcommands), whose every
    /// other option with a long name gets a key. `sections`: top-level keys that are no flag, left to the program
    /// (section()), such as the gateway's `topics:`.
    explicit ConfigFile(CLI::App& command, std::vector<std::string> sections = {});

    /// `args` (the command line without the program's name) with the keys of the file given to --config, when the
    /// command is on it, as the flags they name, in front of the command's own arguments. A flag given on the
    /// command line keeps its value: its key is not used. Throws CLI::ConfigError (exit 2 in the programs) naming
    /// the file, line and column for a file that cannot be read or parsed, an unknown key (with the nearest known
    /// one), or a value that is not what a flag takes.
    std::vector<std::string> with_file(std::vector<std::string> args);

    /// `message` (of an error CLI11 found) with the place and key of the file's key it is about, when the value
    /// came from the file; else as it is.
    std::string explain(const std::string& message) const;

    /// Whether --print-config was given.
    bool print_requested() const;

    /// The configuration in force once the command is parsed, as YAML: every option with a value, given or by
    /// default, in the order of --help, then `extra` (the program's sections, already YAML) as it is.
    std::string print(const std::string& extra = "") const;

    /// A section the file has (see the constructor), or an undefined node; with the file's name for messages.
    YAML::Node section(const std::string& name) const;
    /// The file --config named; empty without one.
    const std::string& file() const { return file_; }

  private:
    /// The flags the keys of `file` name, with their values; not those of `given` (on the command line).
    std::vector<std::string> flags_of(const std::string& file, const std::set<const CLI::Option*>& given);
    /// The options that have a key: every one with a long name but --help, --version and these two.
    std::vector<const CLI::Option*> configurable() const;

    CLI::App& command_;
    std::vector<std::string> sections_;
    bool print_ = false;
    std::string file_;
    YAML::Node root_;
    /// An option whose value came from the file: its flag (--robot-domain), its key and where that is.
    struct FromFile {
        std::string flag;
        std::string key;
        ConfigPlace where;
    };
    std::vector<FromFile> from_file_;
};

/// Parses `argc`/`argv` into `app` as App::parse(argc, argv) does, each of `files` (of `app` or of its
/// subcommands) adding the keys of its --config file; throws what App::parse and ConfigFile::with_file throw.
void parse_with_config(CLI::App& app, int argc, const char* const* argv, const std::vector<ConfigFile*>& files);

/// A program's command line as both programs read it: parse_with_config(), and on --help or --version what CLI11
/// prints, on an error its message explained at the file's key (explain_config_error()), on --print-config the
/// configuration in force of the command that has it, followed by what `sections` returns (the program's own
/// sections as YAML, read from the file; what it throws goes to the caller). The exit code when the program is to
/// stop there (0 for those, 2 for an error); none when it is to run.
std::optional<int> read_command_line(CLI::App& app, int argc, const char* const* argv,
                                     const std::vector<ConfigFile*>& files,
                                     const std::function<std::string()>& sections = {});

/// `message` (of an error in a command's flags) explained by each of `files` (ConfigFile::explain).
std::string explain_config_error(std::string message, const std::vector<ConfigFile*>& files);

/// The key of `option`: its first long name in snake_case; empty for one without a long name.
std::string config_key(const CLI::Option& option);

/// The nearest of `known` to `key` when it is near enough to be the key meant (a typo); else empty.
std::string nearest_key(const std::string& key, const std::vector<std::string>& known);

}  // namespace tgw::base
