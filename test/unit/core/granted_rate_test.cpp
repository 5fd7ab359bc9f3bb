#include "core/granted_rate.hpp"

#include <gtest/gtest.h>

namespace tgw::core {
namespace {

TEST(GrantedRateTest, ItsOwnGrantIsTheRateUpToTheSensors) {
    EXPECT_DOUBLE_EQ(granted_rate_bps(60'000, GrantView{18'000, 30'000, false}, 2'000), 18'000);
    EXPECT_DOUBLE_EQ(granted_rate_bps(10'000, GrantView{18'000, std::nullopt, false}, 2'000), 10'000)
        << "the radio is slower";
}

TEST(GrantedRateTest, AGrantBelowTheLeastShareGivesTheLeastShare) {
    EXPECT_DOUBLE_EQ(granted_rate_bps(60'000, GrantView{500, std::nullopt, false}, 2'000), 2'000);
}

TEST(GrantedRateTest, WithoutAGrantOfItsOwnTheLeastShareCountsTwice) {
    EXPECT_DOUBLE_EQ(granted_rate_bps(60'000, GrantView{std::nullopt, 500, false}, 2'000),
                     NEWCOMER_LEAST_SHARE_FACTOR * 2'000);
    EXPECT_DOUBLE_EQ(granted_rate_bps(60'000, GrantView{std::nullopt, std::nullopt, true}, 4'000),
                     NEWCOMER_LEAST_SHARE_FACTOR * 4'000);
}

TEST(GrantedRateTest, WithoutItsOwnGrantItTakesTheNewcomersShare) {
    EXPECT_DOUBLE_EQ(granted_rate_bps(60'000, GrantView{std::nullopt, 6'000, false}, 0), 6'000);
    EXPECT_DOUBLE_EQ(granted_rate_bps(60'000, GrantView{std::nullopt, 90'000, false}, 0), 60'000) << "its sensor";
}

TEST(GrantedRateTest, AGatewayThatHeardNoGrantYetTakesTheJoinShareOfItsSensedRate) {
    EXPECT_DOUBLE_EQ(granted_rate_bps(60'000, GrantView{std::nullopt, std::nullopt, true}, 0), JOIN_SHARE * 60'000);
}

TEST(GrantedRateTest, WithNoGrantInForceAndPastTheJoinItIsTheSensorsRate) {
    EXPECT_DOUBLE_EQ(granted_rate_bps(60'000, GrantView{}, 2'000), 60'000);
}

}  // namespace
}  // namespace tgw::core
