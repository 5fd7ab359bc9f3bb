#pragma once

#include <optional>
#include <string_view>

#include "base/time.hpp"

namespace tgw::passthrough {

/// Where a topic's TTL came from (docs/design.md §4), first that applies.
enum class TtlSource {
    rule,       ///< the topic's rule in the configuration file (TopicRule::ttl)
    profile,    ///< a data_writer profile named after the topic in the --qos file: the operator's intent
    publisher,  ///< the Lifespan QoS of the discovered publisher
    fallback,   ///< the gateway's --default-ttl
};

std::string_view to_string(TtlSource source);

struct ResolvedTtl {
    base::Duration ttl{};
    TtlSource source = TtlSource::fallback;
};

/// Pure rule of docs/design.md §4. A lifespan that is absent, infinite or not positive does not apply.
ResolvedTtl resolve_ttl(std::optional<base::Duration> profile_lifespan,
                        std::optional<base::Duration> publisher_lifespan, base::Duration default_ttl);
/// The same, a rule's TTL (when it has one) first.
ResolvedTtl resolve_ttl(std::optional<base::Duration> rule_ttl, std::optional<base::Duration> profile_lifespan,
                        std::optional<base::Duration> publisher_lifespan, base::Duration default_ttl);

}  // namespace tgw::passthrough
