#include "passthrough/ttl_resolver.hpp"

namespace tgw::passthrough {

namespace {

bool applies(const std::optional<base::Duration>& lifespan) {
    return lifespan.has_value() && *lifespan > base::Duration::zero() && *lifespan != base::Duration::max();
}

}  // namespace

std::string_view to_string(TtlSource source) {
    switch (source) {
        case TtlSource::rule:
            return "rule";
        case TtlSource::profile:
            return "profile";
        case TtlSource::publisher:
            return "publisher";
        case TtlSource::fallback:
            return "default";
    }
    return "?";
}

ResolvedTtl resolve_ttl(std::optional<base::Duration> profile_lifespan,
                        std::optional<base::Duration> publisher_lifespan, base::Duration default_ttl) {
    if (applies(profile_lifespan)) {
        return {*profile_lifespan, TtlSource::profile};
    }
    if (applies(publisher_lifespan)) {
        return {*publisher_lifespan, TtlSource::publisher};
    }
    return {default_ttl, TtlSource::fallback};
}

ResolvedTtl resolve_ttl(std::optional<base::Duration> rule_ttl, std::optional<base::Duration> profile_lifespan,
                        std::optional<base::Duration> publisher_lifespan, base::Duration default_ttl) {
    if (applies(rule_ttl)) {
        return {*rule_ttl, TtlSource::rule};
    }
    return resolve_ttl(profile_lifespan, publisher_lifespan, default_ttl);
}

}  // namespace tgw::passthrough
