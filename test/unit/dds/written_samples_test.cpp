#include "gateway/dds/written_samples.hpp"

#include <gtest/gtest.h>

namespace tgw::dds {
namespace {

using std::chrono::seconds;

constexpr std::uint32_t WRITER = 0x00000102;
constexpr std::uint32_t OTHER_WRITER = 0x00000202;

class WrittenSamplesTest : public ::testing::Test {
  protected:
    base::SteadyTime at(int s) const { return base::SteadyTime{} + seconds(s); }
    WrittenSamples sut;
};

TEST_F(WrittenSamplesTest, FindsASampleByWriterAndSequenceUntilItsDeadline) {
    sut.note(WRITER, 1, {7, at(10)}, true);
    sut.note(WRITER, 2, {7, at(11)}, true);
    sut.note(OTHER_WRITER, 1, {8, at(20)}, false);

    const WrittenSamples::Written* second = sut.find(WRITER, 2, at(5));
    ASSERT_NE(second, nullptr);
    EXPECT_EQ(second->topic, 7u);
    EXPECT_EQ(second->deadline, at(11));
    ASSERT_NE(sut.find(OTHER_WRITER, 1, at(5)), nullptr);
    EXPECT_EQ(sut.find(OTHER_WRITER, 1, at(5))->topic, 8u) << "each writer numbers its own samples";
    EXPECT_EQ(sut.find(WRITER, 3, at(5)), nullptr) << "never noted";
    EXPECT_EQ(sut.find(0x999, 1, at(5)), nullptr) << "an unknown writer";
    EXPECT_EQ(sut.find(WRITER, 1, at(10)), nullptr) << "at its deadline: no use any more";
    EXPECT_NE(sut.find(WRITER, 2, at(10)), nullptr);
}

TEST_F(WrittenSamplesTest, ASampleNotedAgainOrOutOfOrderIsKeptOnceInSequence) {
    sut.note(WRITER, 5, {1, at(10)}, true);
    sut.note(WRITER, 5, {1, at(12)}, true);  // its message to a second reader
    sut.note(WRITER, 3, {2, at(9)}, true);
    sut.note(WRITER, 4, {3, at(9)}, true);

    EXPECT_EQ(sut.size(), 3u);
    EXPECT_EQ(sut.find(WRITER, 5, at(0))->deadline, at(12));
    EXPECT_EQ(sut.find(WRITER, 3, at(0))->topic, 2u);
    EXPECT_EQ(sut.find(WRITER, 4, at(0))->topic, 3u);
}

TEST_F(WrittenSamplesTest, PruneForgetsEachWritersOldestPastTheirDeadlines) {
    for (int s = 1; s <= 10; ++s) {
        sut.note(WRITER, s, {1, at(s)}, true);
    }
    sut.note(OTHER_WRITER, 1, {2, at(100)}, false);
    sut.note(OTHER_WRITER, 2, {2, at(1)}, false);  // behind a later deadline: kept, never found

    sut.prune(at(4));

    EXPECT_EQ(sut.size(), 6u + 2u);
    EXPECT_EQ(sut.find(WRITER, 4, at(0)), nullptr) << "forgotten";
    EXPECT_NE(sut.find(WRITER, 5, at(0)), nullptr);
    EXPECT_EQ(sut.find(OTHER_WRITER, 2, at(4)), nullptr);
    sut.prune(at(100));
    EXPECT_EQ(sut.size(), 0u);
}

TEST_F(WrittenSamplesTest, AWriterIsExpiringOnceAVolatileSampleOfItsWasNotedUntilCleared) {
    sut.note(WRITER, 1, {1, at(1)}, true);
    sut.note(OTHER_WRITER, 1, {2, at(1)}, false);  // a latched writer's: its history serves late joiners
    sut.prune(at(5));

    EXPECT_TRUE(sut.expiring(WRITER)) << "past its samples' deadlines, still known as volatile";
    EXPECT_FALSE(sut.expiring(OTHER_WRITER));
    EXPECT_FALSE(sut.expiring(0x999));
    sut.clear();
    EXPECT_FALSE(sut.expiring(WRITER));
    EXPECT_EQ(sut.size(), 0u);
}

}  // namespace
}  // namespace tgw::dds
