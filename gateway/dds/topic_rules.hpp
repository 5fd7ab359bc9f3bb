// The `topics:` rules of the gateway's configuration file: per-topic settings by glob, the first match winning.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/time.hpp"

namespace tgw::dds {

/// One rule: what it sets for the robot topics its glob matches. What it leaves unset comes from the flags.
struct TopicRule {
    /// Whether the topics are bridged, before --allow and --deny.
    enum class Bridge { unset, allow, deny };

    std::string match;                  ///< fnmatch glob on the robot's topic name ('*' matches '/' too)
    std::optional<base::Duration> ttl;  ///< before a --qos profile's and the publisher's Lifespan
    Bridge bridge = Bridge::unset;
    /// The base camp may publish it into the robot domain (--uplink); `match` is then a topic's exact name.
    bool uplink = false;
    double max_rate_hz = 0.0;  ///< core::TopicConfig::max_rate_hz; 0: no cap
    bool latest_only = false;  ///< core::TopicConfig::latest_only
    std::string where;         ///< FILE:LINE:COLUMN of the rule, for messages
};

/// The rules in their file's order.
class TopicRules {
  public:
    TopicRules() = default;
    explicit TopicRules(std::vector<TopicRule> rules) : rules_(std::move(rules)) {}

    /// The first rule whose glob matches `topic`; nullptr for none.
    const TopicRule* rule_for(std::string_view topic) const;
    const std::vector<TopicRule>& rules() const { return rules_; }
    bool empty() const { return rules_.empty(); }

  private:
    std::vector<TopicRule> rules_;
};

/// Whether the glob `glob` matches `topic` as the rules and --allow/--deny match: fnmatch without FNM_PATHNAME.
bool topic_glob_matches(const std::string& glob, std::string_view topic);

}  // namespace tgw::dds
