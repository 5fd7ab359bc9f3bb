// The gateway's status on tgw/status, read by a base-camp reader with the generated type: what it says agrees
// with the gateway's own counters, and it comes less often on a slow link.
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>

#include "GatewayStatusPubSubTypes.h"
#include "PaperWorkloadPubSubTypes.h"
#include "test/integration/gateway_fixture.hpp"
#include "wire/status_topic.hpp"

namespace tgw::test {
namespace {

class StatusTest : public GatewayIntegrationTest {
  protected:
    /// A reader of tgw/status with the defaults a base-camp tool has (reliable, as ROS 2's).
    CollectingReader<idl::GatewayStatus>& status_reader() {
        auto& reader = listener<CollectingReader<idl::GatewayStatus>>();
        fdds::DataReaderQos qos = basecamp_->default_reader_qos();
        qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
        EXPECT_NE(basecamp_->make_reader(wire::STATUS_TOPIC, fdds::TypeSupport(new idl::GatewayStatusPubSubType()), qos,
                                         &reader),
                  nullptr);
        return reader;
    }

    static const idl::TopicStatus* find(const idl::GatewayStatus& status, const std::string& topic) {
        const auto& topics = status.topics();
        const auto it =
            std::find_if(topics.begin(), topics.end(), [&](const idl::TopicStatus& t) { return t.name() == topic; });
        return it == topics.end() ? nullptr : &*it;
    }
};

TEST_F(StatusTest, SaysWhatTheGatewayCountsAboutEachTopic) {
    GatewayConfig c = config();
    c.status_period = 100ms;
    auto& statuses = status_reader();
    start_gateway(c);
    gateway_->set_sensor_description("fixed:50000000");
    const std::string topic = topic_prefix_ + "counted";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    constexpr std::uint64_t N = 25;
    for (std::uint64_t i = 0; i < N; ++i) {
        idl::PaperMessage m;
        m.data(std::vector<std::uint8_t>(41, 7));
        ASSERT_TRUE(writer->write(&m));
    }
    ASSERT_TRUE(wait_until([&] { return wan.count() >= N; })) << "got " << wan.count() << " of " << N;

    // The first status that has seen all of them.
    std::optional<idl::GatewayStatus> last;
    ASSERT_TRUE(wait_until([&] {
        for (const auto& r : statuses.received()) {
            const idl::TopicStatus* t = find(r.data, topic);
            if (t != nullptr && t->forwarded() >= N) {
                last = r.data;
                return true;
            }
        }
        return false;
    })) << "no status counted "
        << N << " forwarded samples (" << statuses.count() << " statuses)";

    const idl::TopicStatus& t = *find(*last, topic);
    const core::TopicCounters counters = gateway_->counters(gateway_->find_topic(topic)->id);
    EXPECT_EQ(t.received(), counters.received);
    EXPECT_EQ(t.forwarded(), counters.forwarded);
    EXPECT_EQ(t.forwarded_wire_bytes(), counters.forwarded_wire_bytes);
    EXPECT_EQ(t.queued_samples(), 0u);
    EXPECT_EQ(t.queued_bytes(), 0u);
    EXPECT_EQ(t.expired() + t.doomed() + t.evicted() + t.oversize() + t.shutdown() + t.write_failed() + t.no_reader() +
                  t.rate_capped() + t.superseded(),
              0u);
    EXPECT_EQ(t.ttl_ms(), 5000u);
    EXPECT_EQ(t.matched_readers(), 1);
    EXPECT_DOUBLE_EQ(last->sensed_rate_bps(), c.scheduler.initial_rate_bps);
    EXPECT_DOUBLE_EQ(last->budget_bps(), c.scheduler.initial_rate_bps * c.scheduler.budget_fraction);
    EXPECT_EQ(last->sensor(), "fixed:50000000");
    EXPECT_DOUBLE_EQ(last->status_period_s(), 0.1) << "a fast link takes the status at the period asked for";
    const auto prefix = gateway_->wan_guid_prefix();
    EXPECT_TRUE(std::equal(std::begin(prefix.value), std::end(prefix.value), last->gateway_prefix().begin()));
    EXPECT_GE(gateway_->statuses_published(), statuses.count());
    const core::TopicCounters sent = gateway_->status_counters();
    EXPECT_GE(sent.forwarded, statuses.count()) << "every status received went through the schedule";
    EXPECT_GT(sent.forwarded_wire_bytes, 0u) << "and was charged to the budget";
}

// At 10,000 bit/s a status every second would take a tenth of the link: it comes less often, at 2 % of the rate.
TEST_F(StatusTest, ComesLessOftenOnASlowLink) {
    GatewayConfig c = config();
    // The first comes after it: by then the reader has matched, and the link has carried the discovery that
    // would otherwise keep a status with a TTL of 1 s from making it.
    c.status_period = 3s;
    c.scheduler.initial_rate_bps = 10'000;
    auto& statuses = status_reader();
    start_gateway(c);
    ASSERT_TRUE(wait_until([&] { return statuses.count() >= 1; }))
        << "no status: " << gateway_->status_counters().received << " made, " << gateway_->status_counters().forwarded
        << " forwarded, " << gateway_->status_counters().queued << " queued, "
        << gateway_->status_counters().dropped_for(core::DropReason::expired) << " expired, "
        << gateway_->status_counters().dropped_for(core::DropReason::doomed) << " doomed";
    const double period = statuses.received().front().data.status_period_s();
    // A status with no topic is about 100 bytes of payload, 238 on the wire: 1,904 bits / 200 bit/s.
    EXPECT_GT(period, 5.0);
    EXPECT_LT(period, 20.0);
    std::this_thread::sleep_for(1s);
    EXPECT_EQ(gateway_->statuses_published(), 1u) << "the next status came before its period";
}

// A sensor behind the delivered-rate check: the status says the sensed rate and the check's cap.
TEST_F(StatusTest, CarriesTheDeliveredRateChecksCap) {
    GatewayConfig c = config();
    c.status_period = 100ms;
    auto& statuses = status_reader();
    start_gateway(c);
    sensor::RateReading reading;
    reading.ok = true;
    reading.rate_bps = 3'000'000;
    reading.cap_bps = 3'000'000;
    reading.detail = "link dropping, delivered 2900000 bit/s, capped at 3000000 bit/s";
    gateway_->apply_reading(reading);
    ASSERT_TRUE(wait_until([&] {
        for (const auto& r : statuses.received()) {
            if (r.data.delivered_cap_bps() > 0) {
                return true;
            }
        }
        return false;
    })) << "no status carried the cap ("
        << statuses.count() << " statuses)";
    const idl::GatewayStatus last = statuses.received().back().data;
    EXPECT_DOUBLE_EQ(last.delivered_cap_bps(), 3'000'000);
    EXPECT_DOUBLE_EQ(last.sensed_rate_bps(), 3'000'000);
    EXPECT_EQ(last.sensor_detail(), reading.detail);
}

// The status is scheduled like a sample with a TTL of 1 s: at 1,000 bit/s its 238 bytes on the wire would take
// 1.9 s, so it cannot arrive in time and is not sent at all (it used to leave outside the schedule regardless).
TEST_F(StatusTest, IsNotSentWhenTheLinkCannotCarryItWithinItsTtl) {
    GatewayConfig c = config();
    c.status_period = 100ms;
    c.scheduler.initial_rate_bps = 1'000;
    auto& statuses = status_reader();
    start_gateway(c);
    ASSERT_TRUE(wait_until([&] { return gateway_->status_counters().received >= 1; })) << "no status made";
    ASSERT_TRUE(wait_until([&] { return gateway_->status_counters().queued == 0; })) << "the status stayed queued";
    const core::TopicCounters sent = gateway_->status_counters();
    EXPECT_EQ(sent.forwarded, 0u);
    EXPECT_EQ(sent.received, 1u);
    EXPECT_EQ(sent.dropped_for(core::DropReason::doomed) + sent.dropped_for(core::DropReason::oversize) +
                  sent.dropped_for(core::DropReason::expired),
              1u);
    EXPECT_EQ(statuses.count(), 0u);
}

// A fleet's base camp tells the robots apart by it: the status names the robot and its topics as the camp has them.
TEST_F(StatusTest, NamesItsRobotAndEachTopicUnderTheRobotsName) {
    GatewayConfig c = config();
    c.status_period = 100ms;
    c.robot_name = "rover1";
    auto& statuses = status_reader();
    start_gateway(c);
    const std::string topic = topic_prefix_ + "named";
    const std::string wan_topic = "rover1/" + topic;
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), wan, nullptr, wan_topic);
    ASSERT_NE(writer, nullptr);
    idl::PaperMessage m;
    m.data(std::vector<std::uint8_t>(41, 7));
    ASSERT_TRUE(writer->write(&m));
    ASSERT_TRUE(wait_until([&] {
        for (const auto& r : statuses.received()) {
            if (find(r.data, wan_topic) != nullptr) {
                return true;
            }
        }
        return false;
    })) << "no status named "
        << wan_topic << " (" << statuses.count() << " statuses)";
    for (const auto& r : statuses.received()) {
        EXPECT_EQ(r.data.robot_name(), "rover1");
        EXPECT_EQ(find(r.data, topic), nullptr) << "never under the robot's own name";
    }
}

}  // namespace
}  // namespace tgw::test
