#pragma once

#include <string>
#include <vector>

namespace tgw::dds {

/// Which robot-domain topics the gateway bridges: --allow and --deny globs (fnmatch syntax) on topic names.
/// No allow glob means every topic is allowed; a deny glob that matches wins over any allow glob.
class TopicFilter {
  public:
    TopicFilter() = default;
    TopicFilter(std::vector<std::string> allow, std::vector<std::string> deny);

    bool admits(const std::string& topic) const;

  private:
    std::vector<std::string> allow_;
    std::vector<std::string> deny_;
};

}  // namespace tgw::dds
