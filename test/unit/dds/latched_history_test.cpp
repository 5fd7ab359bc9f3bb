// LatchedHistory: what a transient-local WAN writer's successor is given again after the WAN participant is made
// anew, so that the base camp's late joiners still get each instance's last change.
#include "gateway/dds/latched_history.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace tgw::dds {
namespace {

using namespace std::chrono_literals;

const base::WallTime T0 = base::WallTime(1'700'000'000s);

core::Sample change(std::uint8_t instance, std::uint8_t value, base::WallTime at = T0,
                    core::SampleKind kind = core::SampleKind::data) {
    core::Sample s;
    s.key.valid = true;
    s.key.bytes[15] = instance;
    s.payload = {0, 1, 0, 0, value};
    s.source_time = at;
    s.kind = kind;
    return s;
}

/// The kept changes as (instance, last payload byte) in the order they come back.
std::vector<std::pair<int, int>> kept(const LatchedHistory& h, base::WallTime now = T0,
                                      std::optional<base::Duration> lifespan = std::nullopt) {
    std::vector<std::pair<int, int>> out;
    for (const core::Sample& s : h.live(now, lifespan)) {
        out.emplace_back(s.key.valid ? s.key.bytes[15] : -1, s.payload.empty() ? -1 : s.payload.back());
    }
    return out;
}

TEST(LatchedHistoryTest, KeepsTheLastChangeOfEachInstanceInTheOrderTheyWereWritten) {
    LatchedHistory sut;
    sut.keep(change(1, 10));
    sut.keep(change(2, 20));
    sut.keep(change(1, 11));
    sut.keep(change(3, 30));
    EXPECT_EQ(kept(sut), (std::vector<std::pair<int, int>>{{2, 20}, {1, 11}, {3, 30}}));
    EXPECT_EQ(sut.size(), 3u);
}

TEST(LatchedHistoryTest, AnUnkeyedTopicIsOneInstance) {
    LatchedHistory sut;
    core::Sample a = change(0, 1);
    a.key.valid = false;
    core::Sample b = change(0, 2);
    b.key.valid = false;
    sut.keep(a);
    sut.keep(b);
    EXPECT_EQ(kept(sut), (std::vector<std::pair<int, int>>{{-1, 2}}));
}

TEST(LatchedHistoryTest, AnInstanceWhoseKeyIsAllZeroIsNotTheUnkeyedOne) {
    LatchedHistory sut;
    core::Sample unkeyed = change(0, 1);
    unkeyed.key.valid = false;
    sut.keep(unkeyed);
    sut.keep(change(0, 2));
    EXPECT_EQ(sut.size(), 2u);
}

TEST(LatchedHistoryTest, ADisposeIsTheInstancesLastChangeAsInTheWritersHistory) {
    LatchedHistory sut;
    sut.keep(change(1, 10));
    core::Sample dispose = change(1, 0, T0, core::SampleKind::dispose);
    dispose.payload.clear();
    sut.keep(dispose);
    const std::vector<core::Sample> live = sut.live(T0, std::nullopt);
    ASSERT_EQ(live.size(), 1u);
    EXPECT_EQ(live[0].kind, core::SampleKind::dispose);
}

TEST(LatchedHistoryTest, AShorterChangeReplacesTheWholeOfItsInstancesLongerOne) {
    LatchedHistory sut;
    core::Sample image = change(1, 10);
    image.payload.assign(6000, 0xAB);
    sut.keep(image);
    sut.keep(change(1, 11));
    const std::vector<core::Sample> live = sut.live(T0, std::nullopt);
    ASSERT_EQ(live.size(), 1u);
    EXPECT_EQ(live[0].payload, (std::vector<std::uint8_t>{0, 1, 0, 0, 11}));
}

TEST(LatchedHistoryTest, LeavesOutWhatIsPastTheWritersLifespan) {
    LatchedHistory sut;
    sut.keep(change(1, 10, T0));
    sut.keep(change(2, 20, T0 + 5s));
    EXPECT_EQ(kept(sut, T0 + 8s, 5s), (std::vector<std::pair<int, int>>{{2, 20}}));
    EXPECT_EQ(kept(sut, T0 + 8s).size(), 2u) << "no Lifespan: kept for ever";
}

TEST(LatchedHistoryTest, HoldsAtMostItsLimitOfInstancesForgettingTheLeastRecentlyWritten) {
    LatchedHistory sut(2);
    sut.keep(change(1, 10));
    sut.keep(change(2, 20));
    sut.keep(change(1, 11));
    sut.keep(change(3, 30));
    EXPECT_EQ(kept(sut), (std::vector<std::pair<int, int>>{{1, 11}, {3, 30}}));
}

TEST(LatchedHistoryTest, TakingAPayloadKeepsTheSameAsCopyingItAndLeavesTheChangeWithoutOne) {
    LatchedHistory sut(2);
    core::Sample first = change(1, 10);
    core::Sample second = change(2, 20);
    core::Sample again = change(1, 11);
    sut.keep_taking_payload(first);
    sut.keep(second);
    sut.keep_taking_payload(again);

    EXPECT_EQ(kept(sut), (std::vector<std::pair<int, int>>{{2, 20}, {1, 11}}));
    EXPECT_TRUE(again.payload.empty());
    EXPECT_TRUE(again.key.valid) << "only the payload is taken";
    EXPECT_EQ(again.source_time, T0);
    EXPECT_EQ(second.payload.size(), 5u) << "copied";
    core::Sample third = change(3, 30);
    sut.keep_taking_payload(third);
    EXPECT_EQ(kept(sut), (std::vector<std::pair<int, int>>{{1, 11}, {3, 30}})) << "its limit holds";
}

}  // namespace
}  // namespace tgw::dds
