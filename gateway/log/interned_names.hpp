// The on-robot log's one copy of each topic and type name, so that a row costs no allocation for its names: the
// gateway writes a row for every sample it forwards.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>

namespace tgw::log {

/// Names kept once each, for the table's life: a mission's topics and types, a few hundred bytes each, never
/// forgotten (a topic retired and bridged again finds its names still here). Not thread-safe.
class InternedNames {
  public:
    /// The table's copy of `name`, valid as long as the table.
    std::string_view intern(std::string_view name) {
        if (const auto found = names_.find(name); found != names_.end()) {
            return found->first;
        }
        auto kept = std::make_unique<const std::string>(name);
        const std::string_view view(*kept);
        names_.emplace(view, std::move(kept));
        return view;
    }

    std::size_t size() const { return names_.size(); }

  private:
    /// Each key views its own value, whose characters do not move when the map rehashes.
    std::unordered_map<std::string_view, std::unique_ptr<const std::string>> names_;
};

}  // namespace tgw::log
