// The `topics:` rules end to end (real participants, a real on-robot log): a capped topic reaches the base camp
// at its cap and the rest is logged as rate_capped; a latest_only topic on a slow link sends its latest value,
// the samples it replaced logged as superseded; a rule's TTL and deny take effect.
#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <string>
#include <thread>

#include "PaperWorkloadPubSubTypes.h"
#include "test/integration/gateway_fixture.hpp"

namespace tgw::test {
namespace {

using namespace std::chrono_literals;

class TopicRulesTest : public GatewayIntegrationTest {
  protected:
    GatewayConfig config_with(std::vector<dds::TopicRule> rules) {
        GatewayConfig c = config();
        c.log_file = temp_file(".db");
        c.topic_rules = dds::TopicRules(std::move(rules));
        return c;
    }

    /// Writes `n` samples `period` apart, each's sequence_number its index; the seconds it took.
    static double publish(fdds::DataWriter* writer, int n, std::chrono::milliseconds period, std::size_t bytes = 41) {
        const auto start = std::chrono::steady_clock::now();
        for (int i = 0; i < n; ++i) {
            idl::PaperMessage msg;
            msg.sequence_number(static_cast<std::uint32_t>(i));
            msg.data(std::vector<std::uint8_t>(bytes, 7));
            EXPECT_TRUE(writer->write(&msg));
            std::this_thread::sleep_until(start + (i + 1) * period);
        }
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
};

TEST_F(TopicRulesTest, ACappedTopicReachesTheCampAtItsCapTheRestLoggedAsRateCapped) {
    dds::TopicRule camera;
    camera.match = topic_prefix_ + "camera/*";
    camera.max_rate_hz = 10;
    camera.ttl = 3s;
    const GatewayConfig c = config_with({camera});
    start_gateway(c);
    const std::string topic = topic_prefix_ + "camera/front";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    const auto bridged = gateway_->find_topic(topic);
    ASSERT_TRUE(bridged);
    EXPECT_EQ(bridged->ttl.source, passthrough::TtlSource::rule);
    EXPECT_EQ(bridged->ttl.ttl, base::Duration(3s));

    constexpr int N = 60;
    const double seconds = publish(writer, N, 20ms);  // 50 Hz
    const core::TopicId id = bridged->id;
    ASSERT_TRUE(wait_until([&] { return gateway_->counters(id).received >= N; })) << gateway_->counters(id).received;
    ASSERT_TRUE(wait_until([&] { return gateway_->counters(id).queued == 0; }));
    const core::TopicCounters counts = gateway_->counters(id);
    std::cout << N << " samples at 50 Hz in " << seconds << " s, capped at 10 Hz: " << counts.forwarded
              << " forwarded, " << counts.dropped_for(core::DropReason::rate_capped) << " rate_capped\n";
    // At most 10 a second over the time the samples came in, one more for the first; at least half that.
    EXPECT_LE(counts.forwarded, static_cast<std::uint64_t>(10 * seconds) + 1) << seconds << " s";
    EXPECT_GE(counts.forwarded, static_cast<std::uint64_t>(5 * seconds));
    EXPECT_EQ(counts.dropped_for(core::DropReason::rate_capped), N - counts.forwarded);
    EXPECT_TRUE(wait_until([&] { return wan.count() >= counts.forwarded; })) << wan.count();
    gateway_->stop();
    EXPECT_EQ(logged_with_reason(c.log_file, "rate_capped"),
              static_cast<std::int64_t>(counts.dropped_for(core::DropReason::rate_capped)));
    expect_balanced();
}

TEST_F(TopicRulesTest, ALatestOnlyTopicOnASlowLinkSendsItsLatestValue) {
    dds::TopicRule pose;
    pose.match = topic_prefix_ + "pose";
    pose.latest_only = true;
    pose.ttl = 10s;
    const GatewayConfig c = config_with({pose});
    start_gateway(c);
    const std::string topic = topic_prefix_ + "pose";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    // 400 B at 20 Hz into 4,000 bit/s: a sample takes about 0.9 s of wire, 18 more come meanwhile.
    gateway_->set_rate(4'000);
    constexpr int N = 40;
    publish(writer, N, 50ms, 400);
    const core::TopicId id = gateway_->find_topic(topic)->id;
    ASSERT_TRUE(wait_until([&] { return gateway_->counters(id).queued == 0; }, 10s));
    ASSERT_TRUE(wait_until([&] { return wan.count() >= gateway_->counters(id).forwarded; }, 5s));
    const core::TopicCounters counts = gateway_->counters(id);
    std::cout << N << " samples of 400 B at 20 Hz into 4,000 bit/s, latest_only: " << counts.forwarded << " forwarded, "
              << counts.dropped_for(core::DropReason::superseded) << " superseded\n";
    EXPECT_EQ(counts.received, static_cast<std::uint64_t>(N));
    EXPECT_LE(counts.forwarded, 8u) << "the latest values, not a backlog of " << N;
    EXPECT_EQ(counts.dropped_for(core::DropReason::superseded), N - counts.forwarded);
    const auto samples = wan.received();
    ASSERT_FALSE(samples.empty());
    EXPECT_EQ(samples.back().data.sequence_number(), static_cast<std::uint32_t>(N - 1)) << "the last value published";
    gateway_->stop();
    EXPECT_EQ(logged_with_reason(c.log_file, "superseded"),
              static_cast<std::int64_t>(counts.dropped_for(core::DropReason::superseded)));
    expect_balanced();
}

TEST_F(TopicRulesTest, ADenyRuleKeepsItsTopicOnTheRobotWhateverTheFlags) {
    GatewayConfig c = config_with({});
    dds::TopicRule debug;
    debug.match = topic_prefix_ + "debug/*";
    debug.bridge = dds::TopicRule::Bridge::deny;
    c.topic_rules = dds::TopicRules({debug});
    c.allow = {topic_prefix_ + "*"};
    start_gateway(c);
    const std::string kept = topic_prefix_ + "debug/map";
    const std::string bridged = topic_prefix_ + "odom";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_NE(bridge<idl::PaperMessagePubSubType>(bridged, robot_writer_qos(*robot_), wan), nullptr);
    ASSERT_NE(
        robot_->make_writer(kept, fdds::TypeSupport(new idl::PaperMessagePubSubType()), robot_writer_qos(*robot_)),
        nullptr);
    std::this_thread::sleep_for(1s);
    EXPECT_FALSE(gateway_->find_topic(kept).has_value());
    EXPECT_TRUE(gateway_->find_topic(bridged).has_value());
}

}  // namespace
}  // namespace tgw::test
