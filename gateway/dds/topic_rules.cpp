#include "gateway/dds/topic_rules.hpp"

#include <fnmatch.h>

namespace tgw::dds {

bool topic_glob_matches(const std::string& glob, std::string_view topic) {
    // No FNM_PATHNAME: '*' also matches '/', so "telemetry/*" and "*" cover nested names.
    return fnmatch(glob.c_str(), std::string(topic).c_str(), 0) == 0;
}

const TopicRule* TopicRules::rule_for(std::string_view topic) const {
    for (const TopicRule& rule : rules_) {
        if (topic_glob_matches(rule.match, topic))
            return &rule;
    }
    return nullptr;
}

}  // namespace tgw::dds
