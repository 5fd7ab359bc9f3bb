#include "gateway/dds/topic_filter.hpp"

#include <fnmatch.h>

#include <utility>

namespace tgw::dds {

namespace {

bool matches_any(const std::vector<std::string>& globs, const std::string& topic) {
    for (const std::string& glob : globs) {
        // No FNM_PATHNAME: '*' also matches '/', so "telemetry/*" and "*" cover nested names.
        if (fnmatch(glob.c_str(), topic.c_str(), 0) == 0) {
            return true;
        }
    }
    return false;
}

}  // namespace

TopicFilter::TopicFilter(std::vector<std::string> allow, std::vector<std::string> deny)
    : allow_(std::move(allow)), deny_(std::move(deny)) {}

bool TopicFilter::admits(const std::string& topic) const {
    if (matches_any(deny_, topic)) {
        return false;
    }
    return allow_.empty() || matches_any(allow_, topic);
}

}  // namespace tgw::dds
