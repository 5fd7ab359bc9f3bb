#include "base/config_file.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <set>
#include <sstream>

namespace tgw::base {
namespace {

constexpr const char* CONFIG_FLAG = "--config";
constexpr const char* PRINT_FLAG = "--print-config";

ConfigPlace place_of(const std::string& file, const YAML::Mark& mark) {
    return ConfigPlace::at(file, mark);
}

[[noreturn]] void fail(const ConfigPlace& where, const std::string& what) {
    throw CLI::ConfigError(where.text() + ": " + what);
}

bool is_flag(const CLI::Option& option) {
    return option.get_expected_min() == 0;
}

bool takes_many(const CLI::Option& option) {
    return option.get_expected_max() > 1;
}

/// The scalars of `value` as the flag's arguments: one for a scalar, each of a list; a map is an error.
std::vector<std::string> values_of(const YAML::Node& value, const std::string& file, const std::string& key) {
    if (value.IsScalar()) {
        return {value.Scalar()};
    }
    if (!value.IsSequence()) {
        fail(place_of(file, value.Mark()), "key '" + key + "': expected a value or a list of values");
    }
    std::vector<std::string> out;
    for (const YAML::Node& item : value) {
        if (!item.IsScalar()) {
            fail(place_of(file, item.Mark()), "key '" + key + "': expected a value in the list");
        }
        out.push_back(item.Scalar());
    }
    return out;
}

/// A key as YAML writes it on a line of its own: `key: value`, the value quoted where YAML needs it.
std::string yaml_line(const std::string& key, const std::vector<std::string>& values, bool list) {
    YAML::Emitter out;
    out << YAML::BeginMap << YAML::Key << key << YAML::Value;
    if (list) {
        out << YAML::Flow << values;
    } else {
        out << values.front();
    }
    out << YAML::EndMap;
    return std::string(out.c_str()) + "\n";
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) {
        row[j] = j;
    }
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

/// Whether `text` names the flag `name` as a word of its own (--wan-peer, not --wan-peer-participants).
bool mentions(const std::string& text, const std::string& name) {
    for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
        const std::size_t end = at + name.size();
        if (end == text.size() || !(std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '-')) {
            return true;
        }
    }
    return false;
}

}  // namespace

ConfigPlace ConfigPlace::at(const std::string& file, const YAML::Mark& mark) {
    return ConfigPlace{file, mark.line + 1, mark.column + 1};
}

std::string ConfigPlace::text() const {
    return file + ":" + std::to_string(line) + ":" + std::to_string(column);
}

std::string config_key(const CLI::Option& option) {
    if (option.get_lnames().empty()) {
        return {};
    }
    std::string key = option.get_lnames().front();
    std::replace(key.begin(), key.end(), '-', '_');
    return key;
}

std::string nearest_key(const std::string& key, const std::vector<std::string>& known) {
    std::string best;
    std::size_t best_distance = std::max<std::size_t>(2, key.size() / 3) + 1;
    for (const std::string& k : known) {
        const std::size_t d = edit_distance(key, k);
        if (d < best_distance) {
            best = k;
            best_distance = d;
        }
    }
    return best;
}

ConfigFile::ConfigFile(CLI::App& command, std::vector<std::string> sections)
    : command_(command), sections_(std::move(sections)) {
    command_.add_option(CONFIG_FLAG, file_,
                        "YAML file of this command's settings: a key per flag, its name in snake_case without the "
                        "dashes, a list where the flag repeats; a flag on the command line wins over the file "
                        "(docs/configuration.md)");
    command_.add_flag(PRINT_FLAG, print_,
                      "print the configuration in force as YAML (a --config file that does the same) and exit");
}

std::vector<std::string> ConfigFile::with_file(std::vector<std::string> args) {
    // Where the command's own arguments begin: after its name, for a subcommand.
    std::size_t begin = 0;
    if (command_.get_parent() != nullptr) {
        const auto named = std::find(args.begin(), args.end(), command_.get_name());
        if (named == args.end()) {
            return args;
        }
        begin = static_cast<std::size_t>(named - args.begin()) + 1;
    }
    std::set<const CLI::Option*> given;
    std::string file;
    for (std::size_t i = begin; i < args.size() && args[i] != "--"; ++i) {
        const std::string& arg = args[i];
        if (arg.rfind("--", 0) == 0) {
            const std::string name = arg.substr(0, arg.find('='));
            if (name == CONFIG_FLAG && file.empty()) {
                file =
                    arg.size() > name.size() ? arg.substr(name.size() + 1) : (i + 1 < args.size() ? args[i + 1] : "");
            }
            if (const CLI::Option* option = command_.get_option_no_throw(name)) {
                given.insert(option);
            }
        }
    }
    if (!file.empty()) {
        const std::vector<std::string> from_file = flags_of(file, given);
        args.insert(args.begin() + static_cast<std::ptrdiff_t>(begin), from_file.begin(), from_file.end());
    }
    return args;
}

void parse_with_config(CLI::App& app, int argc, const char* const* argv, const std::vector<ConfigFile*>& files) {
    if (argc > 0 && app.get_name().empty()) {
        app.name(argv[0]);  // as App::parse(argc, argv) names it, for --help
    }
    std::vector<std::string> args(argv + std::min(argc, 1), argv + argc);
    for (ConfigFile* file : files) {
        args = file->with_file(std::move(args));
    }
    std::reverse(args.begin(), args.end());  // App::parse(std::vector) takes the last first
    app.parse(std::move(args));
}

std::optional<int> read_command_line(CLI::App& app, int argc, const char* const* argv,
                                     const std::vector<ConfigFile*>& files,
                                     const std::function<std::string()>& sections) {
    try {
        parse_with_config(app, argc, argv, files);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) {
            return app.exit(e);  // --help, --version
        }
        app.exit(CLI::ConfigError(explain_config_error(e.what(), files)));
        return 2;
    }
    for (const ConfigFile* file : files) {
        if (file->print_requested()) {
            std::fputs(file->print(sections ? sections() : std::string()).c_str(), stdout);
            return 0;
        }
    }
    return std::nullopt;
}

std::string explain_config_error(std::string message, const std::vector<ConfigFile*>& files) {
    for (const ConfigFile* file : files) {
        message = file->explain(message);
    }
    return message;
}

std::vector<std::string> ConfigFile::flags_of(const std::string& file, const std::set<const CLI::Option*>& given) {
    file_ = file;
    try {
        root_ = YAML::LoadFile(file);
    } catch (const YAML::BadFile&) {
        throw CLI::ConfigError(file + ": cannot read the configuration file");
    } catch (const YAML::ParserException& e) {
        fail(place_of(file, e.mark), "not YAML: " + e.msg);
    }
    if (root_.IsNull()) {
        return {};
    }
    if (!root_.IsMap()) {
        fail(place_of(file, root_.Mark()), "expected keys and their values (a YAML map)");
    }
    std::map<std::string, const CLI::Option*> options;
    for (const CLI::Option* option : configurable()) {
        options.emplace(config_key(*option), option);
    }
    std::vector<std::string> flags;
    for (const auto& entry : root_) {
        const std::string key = entry.first.Scalar();
        const ConfigPlace where = place_of(file, entry.first.Mark());
        if (std::find(sections_.begin(), sections_.end(), key) != sections_.end()) {
            continue;
        }
        const auto found = options.find(key);
        if (found == options.end()) {
            std::vector<std::string> known;
            for (const auto& [k, option] : options) {
                known.push_back(k);
            }
            known.insert(known.end(), sections_.begin(), sections_.end());
            const std::string near = nearest_key(key, known);
            fail(where, "unknown key '" + key + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)"));
        }
        const CLI::Option& option = *found->second;
        if (given.count(&option) > 0 || entry.second.IsNull()) {
            continue;  // the command line wins; a key without a value sets nothing
        }
        const std::string flag = "--" + option.get_lnames().front();
        if (is_flag(option)) {
            bool on = false;
            if (!entry.second.IsScalar() || !YAML::convert<bool>::decode(entry.second, on)) {
                fail(place_of(file, entry.second.Mark()), "key '" + key + "': expected true or false");
            }
            if (on) {
                flags.push_back(flag);
            }
        } else {
            for (const std::string& value : values_of(entry.second, file, key)) {
                flags.push_back(flag + "=" + value);
            }
        }
        from_file_.push_back(FromFile{flag, key, where});
    }
    return flags;
}

std::vector<const CLI::Option*> ConfigFile::configurable() const {
    std::vector<const CLI::Option*> out;
    for (const CLI::Option* option : static_cast<const CLI::App&>(command_).get_options()) {
        const std::string key = config_key(*option);
        if (key.empty() || option == command_.get_help_ptr() || key == "help_all" || key == "version" ||
            key == "config" || key == "print_config") {
            continue;
        }
        out.push_back(option);
    }
    return out;
}

std::string ConfigFile::explain(const std::string& message) const {
    for (const FromFile& f : from_file_) {
        if (mentions(message, f.flag)) {
            return f.where.text() + ": key '" + f.key + "': " + message;
        }
    }
    return message;
}

bool ConfigFile::print_requested() const {
    return print_;
}

std::string ConfigFile::print(const std::string& extra) const {
    std::string out = "# The configuration in force (--print-config): a --config file that does the same.\n";
    for (const CLI::Option* option : configurable()) {
        const std::string key = config_key(*option);
        if (is_flag(*option)) {
            bool on = false;
            if (option->count() > 0) {
                on = option->as<bool>();
            }
            out += yaml_line(key, {on ? "true" : "false"}, false);
            continue;
        }
        std::vector<std::string> values = option->results();
        if (option->count() == 0) {
            std::string fallback = option->get_default_str();
            if (takes_many(*option) && fallback.size() >= 2 && fallback.front() == '[' && fallback.back() == ']') {
                std::istringstream items(fallback.substr(1, fallback.size() - 2));
                for (std::string item; std::getline(items, item, ',');) {
                    values.push_back(item);
                }
            } else if (!fallback.empty()) {
                values.push_back(fallback);
            }
        }
        if (values.empty()) {
            out += "# " + key + ":\n";  // not set, and no default to show
        } else {
            out += yaml_line(key, values, takes_many(*option));
        }
    }
    return out + extra;
}

YAML::Node ConfigFile::section(const std::string& name) const {
    if (!root_.IsMap()) {
        return YAML::Node(YAML::NodeType::Undefined);
    }
    const YAML::Node& root = root_;
    return root[name];
}

}  // namespace tgw::base
