#pragma once

namespace tgw::wire {

/// The compact WAN mode's topics (idl/CompactWan.idl): the bundles, and the catalog of what their topic ids mean.
inline constexpr const char* COMPACT_BUNDLE_TOPIC = "tgw/compact/bundles";
inline constexpr const char* COMPACT_CATALOG_TOPIC = "tgw/compact/catalog";

}  // namespace tgw::wire
