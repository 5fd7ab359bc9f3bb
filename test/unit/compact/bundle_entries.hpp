// Bundle entries for the codec's tests and fuzz target.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "compact/bundle_codec.hpp"

namespace tgw::compact::test {

/// An unkeyed, unchunked entry of lane 0.
inline BundleEntry entry(std::uint32_t topic_id, std::int64_t source_ns, std::vector<std::uint8_t> payload,
                         EntryKind kind = EntryKind::data) {
    BundleEntry e;
    e.topic_id = topic_id;
    e.kind = kind;
    e.source_ns = source_ns;
    e.payload = std::move(payload);
    return e;
}

}  // namespace tgw::compact::test
