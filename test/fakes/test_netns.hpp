#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace tgw::test {

/// A network namespace of a test's own, `tgw-PID-TAG-N`, entered on the test's thread so that netlink sockets the
/// test opens see it. Removed (after going back to the original namespace) when destroyed, even when the test
/// failed. Needs root and `ip netns`; skips the test without them.
class TestNetns {
  public:
    TestNetns() = default;
    TestNetns(const TestNetns&) = delete;
    TestNetns& operator=(const TestNetns&) = delete;

    ~TestNetns() {
        if (original_ >= 0) {
            EXPECT_EQ(setns(original_, CLONE_NEWNET), 0);
            close(original_);
        }
        if (created_) {
            EXPECT_TRUE(sh("ip netns del " + name_));
        }
    }

    /// Creates the namespace, runs `commands` inside it and enters it. Call from SetUp() inside
    /// ASSERT_NO_FATAL_FAILURE: it skips the test (GTEST_SKIP) or fails it fatally, then the test does not run.
    void enter(const std::string& tag, const std::vector<std::string>& commands) {
        if (geteuid() != 0) {
            GTEST_SKIP() << "needs root to create network namespaces";
        }
        if (!sh("ip netns list")) {
            GTEST_SKIP() << "`ip netns` is not available";
        }
        static int counter = 0;
        name_ = "tgw-" + std::to_string(getpid()) + "-" + tag + "-" + std::to_string(++counter);
        if (!sh("ip netns add " + name_)) {
            GTEST_SKIP() << "cannot create a network namespace here";
        }
        created_ = true;
        for (const std::string& command : commands) {
            ASSERT_TRUE(run(command)) << command;
        }

        original_ = open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC);
        ASSERT_GE(original_, 0);
        const int target = open(("/run/netns/" + name_).c_str(), O_RDONLY | O_CLOEXEC);
        ASSERT_GE(target, 0);
        const int entered = setns(target, CLONE_NEWNET);
        close(target);
        ASSERT_EQ(entered, 0);
    }

    /// Runs a shell command inside the namespace, its output discarded; true if it succeeded.
    bool run(const std::string& command) const { return sh("ip netns exec " + name_ + " " + command); }

    const std::string& name() const { return name_; }

  private:
    static bool sh(const std::string& command) { return std::system((command + " >/dev/null 2>&1").c_str()) == 0; }

    std::string name_;
    bool created_ = false;
    int original_ = -1;
};

}  // namespace tgw::test
