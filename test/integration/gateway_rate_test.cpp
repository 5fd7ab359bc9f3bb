// The gateway's budget follows the kernel shaper it sends through: a real tbf on a veth inside a network
// namespace of the test's own, read by the qdisc sensor through the gateway's RatePoller.
#include <gtest/gtest.h>

#include "gateway/dds/gateway.hpp"
#include "gateway/dds/rate_poller.hpp"
#include "sensor/rate_sensor.hpp"
#include "test/fakes/test_netns.hpp"
#include "test/integration/dds_test_support.hpp"

namespace tgw::test {
namespace {

using namespace std::chrono_literals;

constexpr auto POLL_INTERVAL = 100ms;

class GatewayRateTest : public ::testing::Test {
  protected:
    void SetUp() override {
        ASSERT_NO_FATAL_FAILURE(
            netns_.enter("gwrate", {"ip link set lo up", "ip link add tgwr0 type veth peer name tgwr1",
                                    "ip link set tgwr0 up", "ip link set tgwr1 up",
                                    "tc qdisc add dev tgwr0 root tbf rate 20kbit burst 1600 "
                                    "latency 1s"}));
        use_transports_in_process();
        const TestDomains domains = TestDomains::for_this_process();
        dds::GatewayConfig config;
        config.robot_domain = domains.robot;
        config.wan_domain = domains.wan;
        config.wan_peers = {"127.0.0.1:" + std::to_string(domains.wan_reader_port)};
        config.wan_interface = "127.0.0.1";
        config.wan_port = domains.gateway_wan_port;
        sensor_ = sensor::make_sensor("qdisc:tgwr0", clock_);
        config.scheduler.initial_rate_bps = sensor_->read().rate_bps;
        sut_ = std::make_unique<dds::Gateway>(config, clock_);
        poller_ = std::make_unique<dds::RatePoller>(
            *sensor_, [this](const sensor::RateReading& r) { sut_->apply_reading(r); }, POLL_INTERVAL);
        poller_->start();
    }
    void TearDown() override {
        poller_.reset();
        sut_.reset();
    }

    TestNetns netns_;
    base::SystemClock clock_;
    std::unique_ptr<sensor::RateSensor> sensor_;
    std::unique_ptr<dds::Gateway> sut_;
    std::unique_ptr<dds::RatePoller> poller_;
};

TEST_F(GatewayRateTest, BudgetStartsAtTheShapersRate) {
    EXPECT_EQ(sut_->rate_bps(), 20'000.0);
}

TEST_F(GatewayRateTest, BudgetFollowsTcQdiscChange) {
    ASSERT_TRUE(netns_.run("tc qdisc change dev tgwr0 root tbf rate 56kbit burst 1600 latency 1s"));
    const auto changed = std::chrono::steady_clock::now();
    // One interval is the contract; the wait allows for a loaded machine, and the time taken is reported.
    EXPECT_TRUE(wait_until([&] { return sut_->rate_bps() == 56'000.0; }, 5s)) << sut_->rate_bps();
    RecordProperty(
        "follow_ms",
        static_cast<int>(
            std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - changed).count()));
    ASSERT_TRUE(netns_.run("tc qdisc change dev tgwr0 root tbf rate 8kbit burst 1600 latency 1s"));
    EXPECT_TRUE(wait_until([&] { return sut_->rate_bps() == 8'000.0; }, 5s)) << sut_->rate_bps();
}

}  // namespace
}  // namespace tgw::test
