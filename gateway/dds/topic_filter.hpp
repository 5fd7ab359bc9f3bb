#pragma once

#include <string>
#include <vector>

#include "gateway/dds/topic_rules.hpp"

namespace tgw::dds {

/// Which robot-domain topics the gateway bridges. A topic's rule (TopicRules::rule_for) that says allow or deny
/// decides; else the --allow and --deny globs (fnmatch syntax) on topic names: no allow glob means every topic is
/// allowed, and a deny glob that matches wins over any allow glob.
class TopicFilter {
  public:
    TopicFilter() = default;
    TopicFilter(std::vector<std::string> allow, std::vector<std::string> deny, TopicRules rules = {});

    bool admits(const std::string& topic) const;

  private:
    std::vector<std::string> allow_;
    std::vector<std::string> deny_;
    TopicRules rules_;
};

}  // namespace tgw::dds
