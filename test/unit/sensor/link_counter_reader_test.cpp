#include "sensor/link_counter_reader.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <linux/if_ether.h>
#include <linux/if_packet.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "base/config_error.hpp"
#include "test/fakes/test_netns.hpp"

namespace tgw::sensor {
namespace {

/// Like QdiscSensorTest: a namespace of its own per test (tgw-PID-counters-N) with a veth pair, a small tbf at
/// the root of tgwa, entered on the test's thread (test::TestNetns); removed even when the test fails.
class LinkCounterReaderTest : public ::testing::Test {
  protected:
    void SetUp() override {
        // 20 kbit/s with room for about three 1,000-byte frames: a burst of ten must queue and drop.
        ASSERT_NO_FATAL_FAILURE(netns_.enter(
            "counters", {"ip link add tgwa type veth peer name tgwb", "ip link set tgwa up", "ip link set tgwb up",
                         "tc qdisc add dev tgwa root tbf rate 20kbit burst 1600 limit 3000"}));
    }

    bool in_netns(const std::string& command) const { return netns_.run(command); }

    /// Sends `count` broadcast Ethernet frames of `size` bytes out of `interface` through its qdisc.
    static void send_frames(const std::string& interface, int count, std::size_t size) {
        const int fd = socket(AF_PACKET, SOCK_RAW | SOCK_CLOEXEC, htons(ETH_P_ALL));
        ASSERT_GE(fd, 0);
        sockaddr_ll to{};
        to.sll_family = AF_PACKET;
        to.sll_ifindex = static_cast<int>(if_nametoindex(interface.c_str()));
        to.sll_halen = ETH_ALEN;
        std::vector<unsigned char> frame(size, 0);
        for (int i = 0; i < ETH_ALEN; ++i) {
            frame[i] = 0xff;  // broadcast
            to.sll_addr[i] = 0xff;
        }
        frame[6] = 0x02;   // a locally administered source
        frame[12] = 0x88;  // EtherType 0x88b5, for local experiments
        frame[13] = 0xb5;
        for (int i = 0; i < count; ++i) {
            sendto(fd, frame.data(), frame.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
        }
        close(fd);
    }

    test::TestNetns netns_;
};

TEST_F(LinkCounterReaderTest, SeesTransmitDropsAndBacklogOfTheShaper) {
    LinkCounterReader sut("tgwa");
    const KernelCountersReading before = sut.read();
    ASSERT_TRUE(before.ok) << before.error;
    send_frames("tgwa", 10, 1'000);
    const KernelCountersReading after = sut.read();
    ASSERT_TRUE(after.ok) << after.error;
    EXPECT_GE(after.counters.tx_bytes - before.counters.tx_bytes, 1'000u);
    EXPECT_GE(after.counters.drops - before.counters.drops, 1u);
    EXPECT_GT(after.counters.backlog_bytes, 0u);
    EXPECT_LE(after.counters.backlog_bytes, 3'000u);
}

TEST_F(LinkCounterReaderTest, ReportsNoDropsOrBacklogWithoutARootQdisc) {
    ASSERT_TRUE(in_netns("tc qdisc del dev tgwa root"));
    LinkCounterReader sut("tgwa");
    send_frames("tgwa", 5, 1'000);
    const KernelCountersReading reading = sut.read();
    ASSERT_TRUE(reading.ok) << reading.error;
    EXPECT_GE(reading.counters.tx_bytes, 5'000u);
    EXPECT_EQ(reading.counters.backlog_bytes, 0u);
}

TEST_F(LinkCounterReaderTest, FailsCleanlyOnceTheInterfaceIsGone) {
    LinkCounterReader sut("tgwa");
    ASSERT_TRUE(in_netns("ip link del tgwa"));
    const KernelCountersReading reading = sut.read();
    EXPECT_FALSE(reading.ok);
    EXPECT_EQ(reading.error.rfind("no interface tgwa", 0), 0u) << reading.error;
}

TEST_F(LinkCounterReaderTest, RefusesToStartOnAMissingInterfaceNamingIt) {
    try {
        LinkCounterReader sut("tgw-nosuch");
        FAIL() << "expected base::ConfigError";
    } catch (const base::ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("no interface tgw-nosuch", 0), 0u) << e.what();
    }
}

}  // namespace
}  // namespace tgw::sensor
