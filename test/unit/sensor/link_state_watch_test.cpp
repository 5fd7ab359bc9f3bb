#include "sensor/link_state_watch.hpp"

#include <gtest/gtest.h>

#include <condition_variable>
#include <mutex>
#include <vector>

#include "test/fakes/test_netns.hpp"

namespace tgw::sensor {
namespace {

using namespace std::chrono_literals;

/// A namespace of the test's own with a veth pair (tgwa, tgwb), both up; the watch follows tgwa. A veth runs only
/// while its peer is up too, as a radio runs only while associated: taking tgwb down is the radio losing its link.
class LinkStateWatchTest : public ::testing::Test {
  protected:
    void SetUp() override {
        ASSERT_NO_FATAL_FAILURE(netns_.enter(
            "linkstate", {"ip link add tgwa type veth peer name tgwb", "ip link set tgwa up", "ip link set tgwb up"}));
    }

    bool in_netns(const std::string& command) const { return netns_.run(command); }

    std::function<void(const LinkState&)> recorder() {
        return [this](const LinkState& state) {
            std::lock_guard<std::mutex> lock(mutex_);
            seen_.push_back(state);
            changed_.notify_all();
        };
    }

    /// Waits (generously: this is about the event arriving, not its speed) until the last state seen is `wanted`.
    bool saw(const LinkState& wanted) {
        std::unique_lock<std::mutex> lock(mutex_);
        return changed_.wait_for(lock, 10s, [&] { return !seen_.empty() && seen_.back() == wanted; });
    }

    std::vector<LinkState> seen() {
        std::lock_guard<std::mutex> lock(mutex_);
        return seen_;
    }

    static inline const LinkState UP{true, true, {}};
    static inline const LinkState DOWN{true, false, {}};
    static inline const LinkState ABSENT{false, false, {}};

    test::TestNetns netns_;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::vector<LinkState> seen_;
};

TEST_F(LinkStateWatchTest, StartsFromTheStateTheInterfaceIsIn) {
    LinkStateWatch sut("tgwa", recorder());
    sut.start();
    ASSERT_EQ(seen().size(), 1u);  // before start() returns
    EXPECT_EQ(seen().front(), UP);
    EXPECT_EQ(sut.state(), UP);
}

TEST_F(LinkStateWatchTest, AnInterfaceDownAtStartIsAStateNotAnError) {
    ASSERT_TRUE(in_netns("ip link set tgwa down"));
    LinkStateWatch sut("tgwa", recorder());
    sut.start();
    EXPECT_EQ(sut.state(), DOWN);
    ASSERT_TRUE(in_netns("ip link set tgwa up"));
    EXPECT_TRUE(saw(UP));
}

TEST_F(LinkStateWatchTest, FollowsTheLinkGoingDownAndComingBack) {
    LinkStateWatch sut("tgwa", recorder());
    sut.start();
    ASSERT_TRUE(in_netns("ip link set tgwb down"));  // the carrier goes: tgwa is up but not running
    EXPECT_TRUE(saw(DOWN));
    ASSERT_TRUE(in_netns("ip link set tgwb up"));
    EXPECT_TRUE(saw(UP));
    EXPECT_EQ(seen(), (std::vector<LinkState>{UP, DOWN, UP}));  // each change once, no repeats
}

TEST_F(LinkStateWatchTest, AnInterfaceThatIsNotThereYetIsAbsentUntilItComes) {
    LinkStateWatch sut("tgwc", recorder());
    sut.start();
    EXPECT_EQ(sut.state(), ABSENT);
    ASSERT_TRUE(in_netns("ip link add tgwc type veth peer name tgwd"));
    EXPECT_TRUE(saw(DOWN));
    ASSERT_TRUE(in_netns("ip link set tgwd up"));
    ASSERT_TRUE(in_netns("ip link set tgwc up"));
    EXPECT_TRUE(saw(UP));
    ASSERT_TRUE(in_netns("ip link del tgwc"));  // unplugged
    EXPECT_TRUE(saw(ABSENT));
}

// A DHCP lease or a mesh radio gives the interface another address while it stays up.
TEST_F(LinkStateWatchTest, FollowsTheInterfacesAddressesAsTheyComeAndGo) {
    LinkStateWatch sut("tgwa", recorder());
    sut.start();
    ASSERT_TRUE(in_netns("ip addr add 10.99.0.1/24 dev tgwa"));
    EXPECT_TRUE(saw(LinkState{true, true, {"10.99.0.1"}}));
    ASSERT_TRUE(in_netns("ip addr add 10.98.0.7/24 dev tgwa"));
    ASSERT_TRUE(in_netns("ip addr del 10.99.0.1/24 dev tgwa"));
    EXPECT_TRUE(saw(LinkState{true, true, {"10.98.0.7"}}));
    EXPECT_TRUE(sut.state().usable());
    ASSERT_TRUE(in_netns("ip addr flush dev tgwa"));
    EXPECT_TRUE(saw(UP));
    EXPECT_FALSE(sut.state().usable());  // up, but nothing IPv4 can leave by it
}

TEST_F(LinkStateWatchTest, StopsPromptlyAndTwice) {
    LinkStateWatch sut("tgwa", recorder(), std::chrono::milliseconds(60'000));
    sut.start();
    sut.stop();  // would hang for the recheck period if the stop did not wake the thread
    sut.stop();
    EXPECT_EQ(seen().size(), 1u);
}

TEST(LinkStateDescribeTest, NamesEachState) {
    EXPECT_STREQ(describe(LinkState{true, true, {"10.77.0.1"}}), "up");
    EXPECT_STREQ(describe(LinkState{true, true, {}}), "up without an IPv4 address");
    EXPECT_STREQ(describe(LinkState{true, false, {}}), "down");
    EXPECT_STREQ(describe(LinkState{false, false, {}}), "absent");
}

}  // namespace
}  // namespace tgw::sensor
