// InternedNames: the on-robot log's rows view the one copy of each name.
#include "gateway/log/interned_names.hpp"

#include <gtest/gtest.h>

#include <string>

namespace tgw::log {
namespace {

TEST(InternedNamesTest, TheSameNameIsTheSameCopy) {
    InternedNames sut;
    std::string caller = "robot1/telemetry/hazard";
    const std::string_view first = sut.intern(caller);
    const std::string_view again = sut.intern(std::string("robot1/telemetry/hazard"));
    EXPECT_EQ(first.data(), again.data());
    EXPECT_EQ(sut.size(), 1u);
    caller.assign("something else entirely, longer than before");
    EXPECT_EQ(first, "robot1/telemetry/hazard") << "the table's copy, not the caller's";
}

TEST(InternedNamesTest, KeptNamesStayPutWhileTheTableGrows) {
    InternedNames sut;
    const std::string_view kept = sut.intern("camera/front/image_raw");
    for (int i = 0; i < 10'000; ++i) {
        sut.intern("topic/" + std::to_string(i));
    }
    EXPECT_EQ(kept, "camera/front/image_raw");
    EXPECT_EQ(sut.intern("camera/front/image_raw").data(), kept.data());
    EXPECT_EQ(sut.size(), 10'001u);
}

}  // namespace
}  // namespace tgw::log
