#include "gateway/dds/topic_filter.hpp"

#include <utility>

namespace tgw::dds {

namespace {

bool matches_any(const std::vector<std::string>& globs, const std::string& topic) {
    for (const std::string& glob : globs) {
        if (topic_glob_matches(glob, topic))
            return true;
    }
    return false;
}

}  // namespace

TopicFilter::TopicFilter(std::vector<std::string> allow, std::vector<std::string> deny, TopicRules rules)
    : allow_(std::move(allow)), deny_(std::move(deny)), rules_(std::move(rules)) {}

bool TopicFilter::admits(const std::string& topic) const {
    if (const TopicRule* rule = rules_.rule_for(topic); rule && rule->bridge != TopicRule::Bridge::unset)
        return rule->bridge == TopicRule::Bridge::allow;
    if (matches_any(deny_, topic)) {
        return false;
    }
    return allow_.empty() || matches_any(allow_, topic);
}

}  // namespace tgw::dds
