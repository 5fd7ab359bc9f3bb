// The `topics:` rules: the first whose glob matches is a topic's rule; it decides the topic's bridging before
// --allow and --deny, and its TTL before a --qos profile's and the publisher's Lifespan. Read from YAML with
// every error at its file, line and column.
#include "gateway/dds/topic_rules.hpp"

#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include "base/config_error.hpp"
#include "gateway/apps/telemetry_gateway/topic_rules_file.hpp"
#include "gateway/dds/topic_filter.hpp"
#include "passthrough/ttl_resolver.hpp"

namespace tgw::dds {
namespace {

using namespace std::chrono_literals;

TopicRule rule(std::string match) {
    TopicRule r;
    r.match = std::move(match);
    return r;
}

TopicRule denying(std::string match) {
    TopicRule r = rule(std::move(match));
    r.bridge = TopicRule::Bridge::deny;
    return r;
}

TopicRule allowing(std::string match) {
    TopicRule r = rule(std::move(match));
    r.bridge = TopicRule::Bridge::allow;
    return r;
}

TEST(TopicRulesTest, TheFirstMatchingRuleIsTheTopicsRule) {
    TopicRule camera = rule("rt/camera/*");
    camera.max_rate_hz = 5;
    TopicRule everything = rule("*");
    everything.ttl = 2s;
    const TopicRules rules({camera, everything});
    ASSERT_NE(rules.rule_for("rt/camera/front/image"), nullptr);
    EXPECT_EQ(rules.rule_for("rt/camera/front/image")->max_rate_hz, 5);
    EXPECT_FALSE(rules.rule_for("rt/camera/front/image")->ttl.has_value()) << "the first match wins, whole";
    EXPECT_EQ(rules.rule_for("rt/odom")->ttl, base::Duration(2s));
    EXPECT_EQ(TopicRules({camera}).rule_for("rt/odom"), nullptr);
}

TEST(TopicRulesTest, ARuleDecidesBridgingBeforeAllowAndDeny) {
    const TopicFilter sut({"telemetry/*"}, {"telemetry/debug*"},
                          TopicRules({allowing("telemetry/debug_pose"), denying("telemetry/D"), rule("telemetry/C")}));
    EXPECT_TRUE(sut.admits("telemetry/debug_pose")) << "allowed by its rule though --deny matches";
    EXPECT_FALSE(sut.admits("telemetry/debug_map"));
    EXPECT_FALSE(sut.admits("telemetry/D"));
    EXPECT_TRUE(sut.admits("telemetry/C")) << "a rule that says neither leaves it to the flags";
    EXPECT_FALSE(sut.admits("rt/chatter"));
}

TEST(TopicRulesTest, ARulesTtlComesFirst) {
    const auto sut = passthrough::resolve_ttl(base::Duration(1s), base::Duration(7s), base::Duration(3s), 5s);
    EXPECT_EQ(sut.ttl, base::Duration(1s));
    EXPECT_EQ(sut.source, passthrough::TtlSource::rule);
    EXPECT_EQ(to_string(sut.source), "rule");
    const auto without = passthrough::resolve_ttl(std::nullopt, base::Duration(7s), base::Duration(3s), 5s);
    EXPECT_EQ(without.source, passthrough::TtlSource::profile);
}

TopicRules read(const std::string& yaml) {
    return gateway_app::read_topic_rules(YAML::Load(yaml)["topics"], "gateway.yaml");
}

std::string error_of(const std::string& yaml) {
    try {
        read(yaml);
    } catch (const base::ConfigError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(TopicRulesFileTest, ReadsEveryKey) {
    const TopicRules rules = read(R"(topics:
  - match: "rt/camera/*"
    max_rate_hz: 5
    ttl: 2.5
  - match: rt/pose
    latest_only: true
  - match: rt/cmd_vel
    uplink: true
    ttl: 0.5
  - match: "rt/debug/*"
    deny: true
  - match: rt/debug/important
    allow: yes
)");
    ASSERT_EQ(rules.rules().size(), 5u);
    const TopicRule& camera = rules.rules()[0];
    EXPECT_EQ(camera.match, "rt/camera/*");
    EXPECT_EQ(camera.max_rate_hz, 5);
    EXPECT_EQ(camera.ttl, base::from_seconds(2.5));
    EXPECT_EQ(camera.where, "gateway.yaml:2:5");
    EXPECT_TRUE(rules.rules()[1].latest_only);
    EXPECT_TRUE(rules.rules()[2].uplink);
    EXPECT_EQ(rules.rules()[3].bridge, TopicRule::Bridge::deny);
    EXPECT_EQ(rules.rules()[4].bridge, TopicRule::Bridge::allow);
}

TEST(TopicRulesFileTest, NoSectionNoRules) {
    EXPECT_TRUE(read("robot_domain: 0\n").empty());
    EXPECT_TRUE(read("topics:\n").empty());
}

TEST(TopicRulesFileTest, PrintsRulesThatReadTheSame) {
    const TopicRules rules = read(R"(topics:
  - {match: "rt/camera/*", max_rate_hz: 5, ttl: 2}
  - {match: rt/pose, latest_only: true, deny: false}
  - {match: rt/cmd_vel, uplink: true}
  - {match: "x/*", deny: true}
)");
    const std::string printed = gateway_app::topic_rules_yaml(rules);
    const TopicRules again = read(printed);
    ASSERT_EQ(again.rules().size(), 4u) << printed;
    EXPECT_EQ(gateway_app::topic_rules_yaml(again), printed);
    EXPECT_EQ(again.rules()[0].max_rate_hz, 5);
    EXPECT_EQ(again.rules()[0].ttl, base::Duration(2s));
    EXPECT_TRUE(again.rules()[1].latest_only);
    EXPECT_EQ(again.rules()[1].bridge, TopicRule::Bridge::unset);
    EXPECT_TRUE(again.rules()[2].uplink);
    EXPECT_EQ(again.rules()[3].bridge, TopicRule::Bridge::deny);
    EXPECT_EQ(gateway_app::topic_rules_yaml(TopicRules{}), "");
}

TEST(TopicRulesFileTest, EachErrorNamesItsPlaceRuleAndKey) {
    EXPECT_EQ(error_of("topics: rt/pose\n"),
              "gateway.yaml:1:9: key 'topics': expected a list of rules ('- match: GLOB', then what it sets)");
    EXPECT_EQ(error_of("topics:\n  - rt/pose\n"),
              "gateway.yaml:2:5: topics[0]: expected a rule: a map with 'match' (a glob of topic names) and what it "
              "sets");
    EXPECT_EQ(error_of("topics:\n  - match: a\n  - match: b\n    latest_onyl: true\n"),
              "gateway.yaml:4:5: topics[1]: unknown key 'latest_onyl' (did you mean 'latest_only'?)");
    EXPECT_EQ(error_of("topics:\n  - ttl: 2\n"),
              "gateway.yaml:2:5: topics[0]: 'match': expected the glob of the topic names it is for (fnmatch: "
              "rt/camera/*)");
    EXPECT_EQ(error_of("topics:\n  - match: a\n    ttl: soon\n"),
              "gateway.yaml:3:10: topics[0]: 'ttl': expected seconds, a number above 0");
    EXPECT_EQ(error_of("topics:\n  - match: a\n    max_rate_hz: 0\n"),
              "gateway.yaml:3:18: topics[0]: 'max_rate_hz': expected samples a second, a number above 0");
    EXPECT_EQ(error_of("topics:\n  - match: a\n    latest_only: maybe\n"),
              "gateway.yaml:3:18: topics[0]: 'latest_only': expected true or false");
    EXPECT_EQ(error_of("topics:\n  - match: a\n    allow: true\n    deny: true\n"),
              "gateway.yaml:4:11: topics[0]: 'allow' excludes 'deny'");
    EXPECT_EQ(error_of("topics:\n  - match: \"rt/*\"\n    uplink: true\n"),
              "gateway.yaml:3:13: topics[0]: 'uplink' needs one topic's exact name in 'match', not a glob: what may "
              "command a robot is spelled out");
}

}  // namespace
}  // namespace tgw::dds
