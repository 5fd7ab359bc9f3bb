// The gateway's `topics:` section of its --config file: read into TopicRules, and printed back by --print-config.
#pragma once

#include <string>

#include <yaml-cpp/yaml.h>

#include "gateway/dds/topic_rules.hpp"

namespace tgw::gateway_app {

/// The rules of `section` (ConfigFile::section("topics") of `file`): a list of maps, each with `match` (a glob)
/// and what it sets. Undefined or null: none. Throws base::ConfigError naming the file, line, column, rule and key
/// of anything else: not a list, an unknown key (with the nearest known), a value of the wrong kind, allow with
/// deny, uplink on a glob.
dds::TopicRules read_topic_rules(const YAML::Node& section, const std::string& file);

/// `rules` as the `topics:` section of a --config file; empty for none.
std::string topic_rules_yaml(const dds::TopicRules& rules);

}  // namespace tgw::gateway_app
