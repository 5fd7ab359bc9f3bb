#include "passthrough/ttl_resolver.hpp"

#include <gtest/gtest.h>

namespace tgw::passthrough {
namespace {

using namespace std::chrono_literals;

TEST(TtlResolverTest, ProfileWinsOverPublisherAndDefault) {
    const auto sut = resolve_ttl(7s, 3s, 5s);
    EXPECT_EQ(sut.ttl, base::Duration(7s));
    EXPECT_EQ(sut.source, TtlSource::profile);
}

TEST(TtlResolverTest, PublisherLifespanWinsOverDefault) {
    const auto sut = resolve_ttl(std::nullopt, 3s, 5s);
    EXPECT_EQ(sut.ttl, base::Duration(3s));
    EXPECT_EQ(sut.source, TtlSource::publisher);
}

TEST(TtlResolverTest, InfiniteOrZeroLifespansDoNotApply) {
    const auto sut = resolve_ttl(base::Duration::max(), base::Duration::zero(), 5s);
    EXPECT_EQ(sut.ttl, base::Duration(5s));
    EXPECT_EQ(sut.source, TtlSource::fallback);
}

}  // namespace
}  // namespace tgw::passthrough
