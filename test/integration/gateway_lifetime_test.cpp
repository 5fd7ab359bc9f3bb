// The gateway's start and stop against a robot domain and a base camp that are already busy: publishers present
// before it starts are all bridged, and receiver reports that keep coming while it stops reach nothing that is
// gone (the ASan build of scripts/test-sanitizers sees a use after free where this test alone sees nothing).
#include <gtest/gtest.h>

#include <atomic>
#include <map>
#include <thread>
#include <vector>

#include "PaperWorkloadPubSubTypes.h"
#include "basecamp/capture/receiver_reporter.hpp"
#include "test/integration/gateway_fixture.hpp"

namespace tgw::test {
namespace {

class GatewayLifetimeTest : public GatewayIntegrationTest {};

TEST_F(GatewayLifetimeTest, PublishersPresentBeforeTheGatewayStartsAreBridgedOnEveryStart) {
    constexpr int TOPICS = 12;
    std::vector<std::string> topics;
    for (int i = 0; i < TOPICS; ++i) {
        topics.push_back(topic_prefix_ + "present" + std::to_string(i));
        ASSERT_NE(robot_->make_writer(topics.back(), fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                      robot_writer_qos(*robot_)),
                  nullptr);
    }
    for (int start = 0; start < 3; ++start) {
        start_gateway(config());
        for (const std::string& topic : topics) {
            EXPECT_TRUE(gateway_->wait_for_topic(topic, MATCH_TIMEOUT))
                << "start " << start << ": " << topic << ", published before the gateway started, was never bridged";
        }
        gateway_.reset();
    }
}

TEST_F(GatewayLifetimeTest, ReceiverReportsArrivingWhileTheGatewayStopsAreHarmless) {
    basecamp::ReceiverReporter reporter(basecamp_->participant());
    for (int round = 0; round < 3; ++round) {
        GatewayConfig c = config();
        c.receiver_reports = true;
        start_gateway(c);
        basecamp::ParticipantPrefix prefix{};
        const auto own = gateway_->wan_guid_prefix();
        std::copy(std::begin(own.value), std::end(own.value), prefix.begin());
        std::map<basecamp::ParticipantPrefix, basecamp::DeliveryTotals> totals{{prefix, {1, 41, 0}}};
        ASSERT_TRUE(wait_until([&] {
            reporter.publish(totals);
            return gateway_->receiver_report().has_value();
        })) << "round "
            << round << ": the gateway never took a report";

        std::atomic<bool> stopping{false};
        std::thread reporting([&] {
            for (std::uint64_t n = 2; !stopping; ++n) {
                totals[prefix].received_samples = n;
                reporter.publish(totals);
                std::this_thread::sleep_for(std::chrono::microseconds(200));
            }
        });
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        gateway_.reset();  // while reports arrive
        stopping = true;
        reporting.join();
    }
}

}  // namespace
}  // namespace tgw::test
