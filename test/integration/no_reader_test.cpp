// Nothing is sent to no one: while no base-camp reader matches a topic, the gateway holds its samples until their
// deadline and then logs them as no_reader (real participants, a real on-robot log).
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "PaperWorkloadPubSubTypes.h"
#include "test/integration/gateway_fixture.hpp"

namespace tgw::test {
namespace {

using namespace std::chrono_literals;

class NoReaderTest : public GatewayIntegrationTest {
  protected:
    /// Publishes `n` samples of `topic` (Lifespan `lifespan`) from a volatile robot writer the gateway has bridged,
    /// with no base-camp reader, once the gateway has them all. Their topic's id, or nullopt with the failure recorded.
    std::optional<core::TopicId> publish_unread(const std::string& topic, base::Duration lifespan, std::uint64_t n) {
        auto& writer_matches = listener<MatchCounter>();
        fdds::DataWriterQos qos = robot_writer_qos(*robot_, lifespan);
        // Volatile, as telemetry is (ROS 2's default): a transient-local lane's WAN writer keeps what it writes
        // for readers that join later, so the gateway writes it whether a reader is there or not.
        qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
        auto* writer =
            robot_->make_writer(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()), qos, &writer_matches);
        if (writer == nullptr || !gateway_->wait_for_topic(topic, MATCH_TIMEOUT) ||
            !wait_until([&] { return writer_matches.matched.load() > 0; }, MATCH_TIMEOUT)) {
            ADD_FAILURE() << "the gateway never bridged " << topic;
            return std::nullopt;
        }
        for (std::uint64_t i = 0; i < n; ++i) {
            idl::PaperMessage msg;
            msg.sequence_number(static_cast<std::uint32_t>(i));
            msg.data(std::vector<std::uint8_t>(41, 7));
            if (!writer->write(&msg)) {
                ADD_FAILURE() << "the robot writer refused sample " << i;
                return std::nullopt;
            }
        }
        const core::TopicId id = gateway_->find_topic(topic)->id;
        if (!wait_until([&] { return gateway_->counters(id).received >= n; })) {
            ADD_FAILURE() << "the gateway received " << gateway_->counters(id).received << " of " << n;
            return std::nullopt;
        }
        return id;
    }
};

TEST_F(NoReaderTest, ABurstWrittenBeforeTheBaseCampReadsArrivesWholeOnceItDoes) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "burst";
    constexpr std::uint64_t N = 300;
    const auto published = publish_unread(topic, 20s, N);
    ASSERT_TRUE(published);
    const core::TopicId id = *published;
    EXPECT_EQ(gateway_->counters(id).forwarded, 0u);
    EXPECT_EQ(gateway_->counters(id).queued, N);

    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_NE(basecamp_->make_reader(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                     wan_reader_qos(*basecamp_), &wan),
              nullptr);
    ASSERT_TRUE(wait_until([&] { return wan.count() >= N; }, MATCH_TIMEOUT))
        << wan.count() << " of " << N << " arrived; forwarded " << gateway_->counters(id).forwarded;
    EXPECT_EQ(gateway_->counters(id).forwarded, N);
    expect_balanced();
}

TEST_F(NoReaderTest, SamplesNoOneReadsByTheirDeadlineGoToTheLogAsNoReader) {
    GatewayConfig c = config();
    c.log_file = temp_file(".db");
    start_gateway(c);
    const std::string topic = topic_prefix_ + "unread";
    constexpr std::uint64_t N = 20;
    const auto published = publish_unread(topic, 1s, N);
    ASSERT_TRUE(published);
    const core::TopicId id = *published;
    ASSERT_TRUE(wait_until([&] { return gateway_->counters(id).dropped_for(core::DropReason::no_reader) >= N; }, 5s));
    const core::TopicCounters after = gateway_->counters(id);
    EXPECT_EQ(after.received, N);
    EXPECT_EQ(after.forwarded, 0u);
    EXPECT_EQ(after.dropped_total(), N);
    gateway_->stop();
    EXPECT_EQ(logged_with_reason(c.log_file, "no_reader"), static_cast<std::int64_t>(N));
}

}  // namespace
}  // namespace tgw::test
