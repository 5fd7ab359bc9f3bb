// --config FILE.yaml: the keys of a real file on disk become the flags they name, through CLI11 as the programs
// parse; the command line wins; errors name the file, line, column and key.
#include "base/config_file.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "test/unit/basecamp/scratch_dir.hpp"

namespace tgw::base {
namespace {

/// A command as the programs make theirs: a few typed options and a flag, and its configuration file.
struct Program {
    explicit Program(CLI::App& command, std::vector<std::string> sections = {}) {
        command.add_option("--robot-domain", robot_domain, "")->capture_default_str();
        command.add_option("--wan-peer", peers, "");
        command.add_option("--wan-peer-participants", participants, "")->capture_default_str();
        command.add_flag("--wan-compress", compress, "");
        command.add_option("--sensor", sensor, "")->capture_default_str();
        command.add_option("--log", log, "");
        config = std::make_unique<ConfigFile>(command, std::move(sections));
    }

    int robot_domain = 0;
    std::vector<std::string> peers;
    int participants = 4;
    bool compress = false;
    std::string sensor = "fixed:50000";
    std::string log;
    std::unique_ptr<ConfigFile> config;
};

class ConfigFileTest : public ::testing::Test {
  protected:
    /// Writes `text` to a file of the scratch directory and gives its path.
    std::string file(const std::string& text, const std::string& name = "gateway.yaml") {
        const std::string path = dir_.file(name);
        std::ofstream(path) << text;
        return path;
    }

    /// Parses `args` (without the program's name) as the programs do; the message of the error it throws, or
    /// empty.
    std::string parse(const std::vector<std::string>& args) {
        std::vector<const char*> argv{"telemetry-gateway"};
        for (const std::string& a : args)
            argv.push_back(a.c_str());
        try {
            parse_with_config(app_, static_cast<int>(argv.size()), argv.data(), {program_.config.get()});
        } catch (const CLI::ParseError& e) {
            return explain_config_error(e.what(), {program_.config.get()});
        }
        return {};
    }

    test::ScratchDir dir_{"tgw-config"};
    CLI::App app_{"telemetry-gateway"};
    Program program_{app_, {"topics"}};
};

TEST_F(ConfigFileTest, EachKeySetsTheFlagItNames) {
    const std::string path = file(
        "robot_domain: 7\nwan_peer: [camp.local, 10.0.0.2]\nwan_compress: true\n"
        "sensor: 'qdisc:wlan0'\n");
    ASSERT_EQ(parse({"--config", path}), "");
    EXPECT_EQ(program_.robot_domain, 7);
    EXPECT_EQ(program_.peers, (std::vector<std::string>{"camp.local", "10.0.0.2"}));
    EXPECT_TRUE(program_.compress);
    EXPECT_EQ(program_.sensor, "qdisc:wlan0");
    EXPECT_EQ(program_.participants, 4) << "a key not in the file leaves the flag's default";
    EXPECT_EQ(program_.config->file(), path);
}

TEST_F(ConfigFileTest, AFlagOnTheCommandLineWinsOverTheFile) {
    const std::string path = file("robot_domain: 7\nwan_peer: [camp.local]\nsensor: fixed:10000\n");
    ASSERT_EQ(parse({"--robot-domain", "3", "--config=" + path, "--wan-peer=backup.local"}), "");
    EXPECT_EQ(program_.robot_domain, 3);
    EXPECT_EQ(program_.peers, std::vector<std::string>{"backup.local"}) << "not added to the file's list";
    EXPECT_EQ(program_.sensor, "fixed:10000");
}

TEST_F(ConfigFileTest, AnUnknownKeyNamesTheFileLineColumnAndTheNearestKnownKey) {
    const std::string path = file("robot_domain: 7\n  # a comment\nwan_peers: [camp.local]\n");
    EXPECT_EQ(parse({"--config", path}), path + ":3:1: unknown key 'wan_peers' (did you mean 'wan_peer'?)");
    const std::string dashed = file("robot-domain: 7\n", "dashed.yaml");
    EXPECT_EQ(parse({"--config", dashed}), dashed + ":1:1: unknown key 'robot-domain' (did you mean 'robot_domain'?)");
    const std::string far = file("bandwidth: 7\n", "far.yaml");
    EXPECT_EQ(parse({"--config", far}), far + ":1:1: unknown key 'bandwidth'");
}

TEST_F(ConfigFileTest, AValueTheFlagCannotTakeIsToldAtItsKeysPlace) {
    const std::string path = file("sensor: fixed:1\nrobot_domain: seven\n");
    const std::string message = parse({"--config", path});
    EXPECT_EQ(message.rfind(path + ":2:1: key 'robot_domain': ", 0), 0u) << message;
    EXPECT_NE(message.find("seven"), std::string::npos) << message;
}

TEST_F(ConfigFileTest, AListForAFlagThatTakesOneValueIsAnErrorAtItsKey) {
    const std::string path = file("robot_domain: [1, 2]\n");
    const std::string message = parse({"--config", path});
    EXPECT_EQ(message.rfind(path + ":1:1: key 'robot_domain': ", 0), 0u) << message;
}

TEST_F(ConfigFileTest, AnOnOffFlagTakesTrueOrFalse) {
    ASSERT_EQ(parse({"--config", file("wan_compress: false\n")}), "");
    EXPECT_FALSE(program_.compress);
    const std::string path = file("\nwan_compress: sometimes\n", "bad.yaml");
    EXPECT_EQ(parse({"--config", path}), path + ":2:15: key 'wan_compress': expected true or false");
}

TEST_F(ConfigFileTest, AMapWhereAValueBelongsIsAnError) {
    const std::string path = file("wan_peer:\n  host: camp.local\n");
    EXPECT_EQ(parse({"--config", path}), path + ":2:3: key 'wan_peer': expected a value or a list of values");
}

TEST_F(ConfigFileTest, AFileThatIsNotYamlIsToldWhereItBreaks) {
    const std::string path = file("robot_domain: 7\nwan_peer: [camp.local\n");
    const std::string message = parse({"--config", path});
    EXPECT_EQ(message.rfind(path + ":", 0), 0u) << message;
    EXPECT_NE(message.find("not YAML"), std::string::npos) << message;
    const std::string list = file("- robot_domain\n", "list.yaml");
    EXPECT_EQ(parse({"--config", list}), list + ":1:1: expected keys and their values (a YAML map)");
}

TEST_F(ConfigFileTest, AFileThatCannotBeReadIsNamed) {
    const std::string path = dir_.file("missing.yaml");
    EXPECT_EQ(parse({"--config", path}), path + ": cannot read the configuration file");
}

TEST_F(ConfigFileTest, AKeyWithoutAValueSetsNothingAndAnEmptyFileNothingAtAll) {
    ASSERT_EQ(parse({"--config", file("robot_domain:\nlog:\n")}), "");
    EXPECT_EQ(program_.robot_domain, 0);
    EXPECT_EQ(program_.log, "");
    ASSERT_EQ(parse({"--config", file("# nothing yet\n", "empty.yaml")}), "");
}

TEST_F(ConfigFileTest, ASectionIsLeftToTheProgram) {
    const std::string path = file("robot_domain: 2\ntopics:\n  - match: 'rt/camera/*'\n    ttl: 2\n");
    ASSERT_EQ(parse({"--config", path}), "");
    const YAML::Node topics = program_.config->section("topics");
    ASSERT_TRUE(topics.IsSequence());
    EXPECT_EQ(topics[0]["match"].as<std::string>(), "rt/camera/*");
    EXPECT_FALSE(program_.config->section("uplink").IsDefined());
}

TEST_F(ConfigFileTest, WhatItPrintsGivenBackDoesTheSame) {
    const std::string path = file("robot_domain: 7\nwan_peer: [camp.local, '10.0.0.2:7412']\nwan_compress: true\n");
    ASSERT_EQ(parse({"--config", path, "--sensor", "trace:radio: log.txt", "--print-config"}), "");
    EXPECT_TRUE(program_.config->print_requested());
    const std::string printed = program_.config->print("topics: []\n");
    EXPECT_NE(printed.find("# log:\n"), std::string::npos) << "a key with no value is shown, commented\n" << printed;

    CLI::App again{"telemetry-gateway"};
    Program second(again, {"topics"});
    const std::string copy = file(printed, "printed.yaml");
    std::vector<const char*> argv{"telemetry-gateway", "--config", copy.c_str()};
    ASSERT_NO_THROW(parse_with_config(again, 3, argv.data(), {second.config.get()})) << printed;
    EXPECT_EQ(second.robot_domain, 7);
    EXPECT_EQ(second.peers, program_.peers);
    EXPECT_TRUE(second.compress);
    EXPECT_EQ(second.sensor, "trace:radio: log.txt");
    EXPECT_EQ(second.participants, 4);
    EXPECT_FALSE(second.config->print_requested()) << "print_config is no key";
    EXPECT_TRUE(second.config->section("topics").IsSequence());
}

TEST(ConfigFileSubcommandTest, ASubcommandReadsTheFileGivenAfterItsName) {
    test::ScratchDir dir{"tgw-config"};
    const std::string path = dir.file("relay.yaml");
    std::ofstream(path) << "robot_domain: 5\nwan_peer: [rover1.local]\n";
    CLI::App app{"tm-basecamp"};
    app.add_subcommand("record", "");
    CLI::App* relay = app.add_subcommand("relay", "");
    Program program(*relay);
    std::vector<const char*> argv{"tm-basecamp", "relay", "--config", path.c_str(), "--robot-domain", "6"};
    parse_with_config(app, static_cast<int>(argv.size()), argv.data(), {program.config.get()});
    EXPECT_TRUE(relay->parsed());
    EXPECT_EQ(program.robot_domain, 6);
    EXPECT_EQ(program.peers, std::vector<std::string>{"rover1.local"});
}

TEST(NearestKeyTest, SuggestsOnlyAKeyNearEnoughToBeATypo) {
    const std::vector<std::string> known{"robot_domain", "wan_domain", "wan_peer", "sensor"};
    EXPECT_EQ(nearest_key("robot_domian", known), "robot_domain");
    EXPECT_EQ(nearest_key("sensr", known), "sensor");
    EXPECT_EQ(nearest_key("peer", known), "");
    EXPECT_EQ(nearest_key("qos", known), "");
}

}  // namespace
}  // namespace tgw::base
