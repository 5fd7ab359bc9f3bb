#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <list>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "base/clock.hpp"
#include "core/sample.hpp"

namespace tgw::dds {

/// A copy of what a transient-local ("latched") WAN writer holds for the base camp's late joiners: the last change
/// of each instance (its history is one deep, passthrough_writer_qos), a dispose or unregister included. When the
/// WAN participant is made anew (an address change) the writer's successor starts with no history; written into
/// it again, these reach a late joiner as the old writer's history would have. Pure; not thread-safe.
class LatchedHistory {
  public:
    /// At most `max_instances` instances, the least recently written forgotten first (the writer's own limit).
    explicit LatchedHistory(std::size_t max_instances = 65'536) : max_instances_(max_instances) {}

    /// Keeps a copy of `change`, in place of its instance's previous one.
    void keep(const core::Sample& change);
    /// The same, taking `change`'s payload instead of copying it (a 4 MiB frame's copy took 450 us): `change` is
    /// left without one.
    void keep_taking_payload(core::Sample& change);

    /// The kept changes, least recently written first, but those past `lifespan` (the writer's; none: infinite)
    /// at `now`, which the writer would have let go of.
    std::vector<core::Sample> live(base::WallTime now, std::optional<base::Duration> lifespan) const;

    std::size_t size() const { return order_.size(); }

  private:
    /// An unkeyed topic's samples, and a keyed topic's without a key, are one instance, apart from every key.
    using Instance = std::pair<bool, std::array<std::uint8_t, 16>>;
    static Instance instance_of(const core::Sample& change);
    /// The node `change` goes into: its instance's, moved to the back, or a new one at the back.
    core::Sample& slot_for(const core::Sample& change);

    std::size_t max_instances_;
    std::list<core::Sample> order_;  // least recently written first
    std::map<Instance, std::list<core::Sample>::iterator> by_instance_;
};

}  // namespace tgw::dds
