#include "gateway/apps/telemetry_gateway/topic_rules_file.hpp"

#include <algorithm>
#include <utility>
#include <vector>

#include "base/config_error.hpp"
#include "base/config_file.hpp"

namespace tgw::gateway_app {

namespace {

/// The keys a rule may have.
const std::vector<std::string> TOPIC_RULE_KEYS = {"match",  "ttl",         "allow",      "deny",
                                                  "uplink", "max_rate_hz", "latest_only"};

/// Reads one rule, each message starting with its place and "topics[INDEX]".
class RuleReader {
  public:
    RuleReader(YAML::Node node, std::string file, std::size_t index)
        : node_(std::move(node)), file_(std::move(file)), name_("topics[" + std::to_string(index) + "]") {}

    dds::TopicRule read() {
        if (!node_.IsMap())
            fail(node_, "expected a rule: a map with 'match' (a glob of topic names) and what it sets");
        for (const auto& entry : node_) {
            const std::string key = entry.first.Scalar();
            if (std::find(TOPIC_RULE_KEYS.begin(), TOPIC_RULE_KEYS.end(), key) == TOPIC_RULE_KEYS.end()) {
                const std::string near = base::nearest_key(key, TOPIC_RULE_KEYS);
                fail(entry.first,
                     "unknown key '" + key + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)"));
            }
        }
        dds::TopicRule rule;
        rule.where = base::ConfigPlace::at(file_, node_.Mark()).text();
        const YAML::Node match = node_["match"];
        if (!match || !match.IsScalar() || match.Scalar().empty())
            fail(match ? match : node_,
                 "'match': expected the glob of the topic names it is for (fnmatch: rt/camera/*)");
        rule.match = match.Scalar();
        if (const YAML::Node ttl = node_["ttl"])
            rule.ttl = base::from_seconds(positive_number(ttl, "ttl", "seconds"));
        if (const YAML::Node rate = node_["max_rate_hz"])
            rule.max_rate_hz = positive_number(rate, "max_rate_hz", "samples a second");
        rule.latest_only = boolean(node_["latest_only"], "latest_only");
        rule.uplink = boolean(node_["uplink"], "uplink");
        const bool allow = boolean(node_["allow"], "allow");
        const bool deny = boolean(node_["deny"], "deny");
        if (allow && deny)
            fail(node_["deny"], "'allow' excludes 'deny'");
        rule.bridge = allow  ? dds::TopicRule::Bridge::allow
                      : deny ? dds::TopicRule::Bridge::deny
                             : dds::TopicRule::Bridge::unset;
        if (rule.uplink && rule.match.find_first_of("*?[") != std::string::npos)
            fail(node_["uplink"],
                 "'uplink' needs one topic's exact name in 'match', not a glob: what may command "
                 "a robot is spelled out");
        return rule;
    }

  private:
    [[noreturn]] void fail(const YAML::Node& at, const std::string& what) const {
        throw base::ConfigError(base::ConfigPlace::at(file_, at.Mark()).text() + ": " + name_ + ": " + what);
    }

    double positive_number(const YAML::Node& value, const std::string& key, const std::string& unit) const {
        double number = 0.0;
        if (!value.IsScalar() || !YAML::convert<double>::decode(value, number) || !(number > 0.0))
            fail(value, "'" + key + "': expected " + unit + ", a number above 0");
        return number;
    }

    bool boolean(const YAML::Node& value, const std::string& key) const {
        if (!value)
            return false;
        bool flag = false;
        if (!value.IsScalar() || !YAML::convert<bool>::decode(value, flag))
            fail(value, "'" + key + "': expected true or false");
        return flag;
    }

    YAML::Node node_;
    std::string file_;
    std::string name_;
};

}  // namespace

dds::TopicRules read_topic_rules(const YAML::Node& section, const std::string& file) {
    if (!section || section.IsNull())
        return {};
    if (!section.IsSequence())
        throw base::ConfigError(base::ConfigPlace::at(file, section.Mark()).text() +
                                ": key 'topics': expected a list of rules ('- match: GLOB', then what it sets)");
    std::vector<dds::TopicRule> rules;
    for (std::size_t i = 0; i < section.size(); ++i)
        rules.push_back(RuleReader(section[i], file, i).read());
    return dds::TopicRules(std::move(rules));
}

std::string topic_rules_yaml(const dds::TopicRules& rules) {
    if (rules.empty())
        return "";
    YAML::Emitter out;
    out << YAML::BeginMap << YAML::Key << "topics" << YAML::Value << YAML::BeginSeq;
    for (const dds::TopicRule& rule : rules.rules()) {
        out << YAML::BeginMap << YAML::Key << "match" << YAML::Value << YAML::DoubleQuoted << rule.match;
        if (rule.ttl)
            out << YAML::Key << "ttl" << YAML::Value << base::to_seconds(*rule.ttl);
        if (rule.bridge != dds::TopicRule::Bridge::unset)
            out << YAML::Key << (rule.bridge == dds::TopicRule::Bridge::allow ? "allow" : "deny") << YAML::Value
                << true;
        if (rule.uplink)
            out << YAML::Key << "uplink" << YAML::Value << true;
        if (rule.max_rate_hz > 0.0)
            out << YAML::Key << "max_rate_hz" << YAML::Value << rule.max_rate_hz;
        if (rule.latest_only)
            out << YAML::Key << "latest_only" << YAML::Value << true;
        out << YAML::EndMap;
    }
    out << YAML::EndSeq << YAML::EndMap;
    return std::string(out.c_str()) + "\n";
}

}  // namespace tgw::gateway_app
