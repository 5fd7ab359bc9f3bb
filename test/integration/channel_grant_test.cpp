// A fleet's shared channel (tm-basecamp relay --channel-rate, telemetry-gateway --channel-grants), with real
// participants: two gateways whose sensors each see the whole radio, and the relay that grants them shares of one
// 30,000 bit/s channel from their statuses. rover1 has hazards to send (TTL 1 s), rover2 a bulk topic (TTL 20 s):
// rover1 gets what its hazards need, rover2 the rest, where equal shares would give each half.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <string>
#include <thread>

#include "PaperWorkloadPubSubTypes.h"
#include "gateway/core/granted_rate.hpp"
#include "test/integration/relay_fixture.hpp"

namespace tgw::test {
namespace {

constexpr double CHANNEL_BPS = 30'000;

using ChannelGrantTest = RelayTest;

TEST_F(ChannelGrantTest, TheRobotWithUrgentSamplesGetsTheirShareFirst) {
    const std::string hazards = topic_prefix_ + "hazards";
    const std::string bulk = topic_prefix_ + "bulk";
    GatewayConfig c1 = config();
    c1.robot_name = "rover1";
    c1.allow = {hazards};
    c1.channel_grants = true;
    c1.status_period = 1s;
    GatewayConfig c2 = c1;
    c2.robot_name = "rover2";
    c2.allow = {bulk};
    c2.wan_port = dds::metatraffic_unicast_port(domains_.wan, 62);
    start_gateway(c1);
    Gateway rover2(c2, clock_);
    start_relay(nullptr, 1s, {}, CHANNEL_BPS);

    // 20 Hz each: rover1's 41-byte hazards need about 38,000 bit/s on the wire, rover2's kilobyte samples more.
    auto* hazard_writer = robot_writer<idl::PaperMessagePubSubType>(hazards, robot_writer_qos(*robot_, 1s));
    auto* bulk_writer = robot_writer<idl::PaperMessagePubSubType>(bulk, robot_writer_qos(*robot_, 20s));
    ASSERT_NE(hazard_writer, nullptr);
    ASSERT_NE(bulk_writer, nullptr);
    std::atomic<bool> stop{false};
    std::thread publish([&] {
        for (std::uint64_t i = 0; !stop.load(); ++i) {
            idl::PaperMessage hazard;
            hazard.sequence_number(static_cast<std::uint32_t>(i));
            hazard.data(std::vector<std::uint8_t>(41, 1));
            hazard_writer->write(&hazard);
            idl::PaperMessage sample;
            sample.sequence_number(static_cast<std::uint32_t>(i));
            sample.data(std::vector<std::uint8_t>(1016, 2));
            bulk_writer->write(&sample);
            std::this_thread::sleep_for(50ms);
        }
    });
    const auto settled = [&] {
        const auto g1 = gateway_->granted_bps();
        const auto g2 = rover2.granted_bps();
        return g1 && g2 && *g1 > 20'000 && *g2 < 10'000;
    };
    const bool ok = wait_until(settled, 30s);
    stop.store(true);
    publish.join();
    ASSERT_TRUE(ok) << "grants: rover1 " << gateway_->granted_bps().value_or(-1) << ", rover2 "
                    << rover2.granted_bps().value_or(-1) << " bit/s";

    // Each gateway budgets for its grant (its sensor, 50 Mbit/s, sees the whole radio), and together no more than
    // the channel.
    const double rate1 = gateway_->rate_bps();
    const double rate2 = rover2.rate_bps();
    EXPECT_GT(rate1, 20'000);
    EXPECT_LT(rate2, 10'000);
    EXPECT_LE(rate1 + rate2, CHANNEL_BPS * 1.001);
    const core::ChannelGrants grants = relay_->channel_grants();
    ASSERT_EQ(grants.size(), 2u);
    double total = 0;
    for (const auto& [gateway, bps] : grants)
        total += bps;
    EXPECT_LE(total, CHANNEL_BPS * 1.001);
}

// A gateway the base camp has no status of (it sends none here) has no grant of its own: it budgets for the
// newcomers' share, a tenth of the channel, not for its sensor's 50 Mbit/s.
TEST_F(ChannelGrantTest, AGatewayWithoutAGrantOfItsOwnBudgetsForTheNewcomersShare) {
    GatewayConfig c = config();
    c.robot_name = "rover1";
    c.channel_grants = true;
    c.status_period = base::Duration::zero();
    start_gateway(c);
    start_relay(nullptr, 1s, {}, CHANNEL_BPS);
    const double newcomers = core::JOIN_SHARE * CHANNEL_BPS;
    const bool ok = wait_until([&] { return std::abs(gateway_->rate_bps() - newcomers) < 1; }, 20s);
    ASSERT_TRUE(ok) << "budgets for " << gateway_->rate_bps() << " bit/s";
    EXPECT_FALSE(gateway_->granted_bps()) << "no grant of its own";
    EXPECT_NEAR(relay_->newcomer_share().value_or(-1), newcomers, 1);
}

}  // namespace
}  // namespace tgw::test
