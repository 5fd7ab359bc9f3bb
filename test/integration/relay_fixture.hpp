// A gateway and tm-basecamp relay in one process: robot writer -> Gateway -> Relay -> readers on the camp's
// local domain, each with real participants on domains of the test's own.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include "basecamp/capture/backfill_archive.hpp"
#include "basecamp/recording/sample_store.hpp"
#include "basecamp/relay/relay.hpp"
#include "test/integration/gateway_fixture.hpp"

namespace tgw::test {

class RelayTest : public GatewayIntegrationTest {
  protected:
    void SetUp() override {
        GatewayIntegrationTest::SetUp();
        // The relay is the base camp's one participant on the WAN domain, on the port the gateway announces to.
        basecamp_.reset();
        local_domain_ = domains_.camp;
        local_ = std::make_unique<TestParticipant>(local_domain_, fdds::PARTICIPANT_QOS_DEFAULT);
        ASSERT_TRUE(local_->ok());
    }

    void TearDown() override {
        stop_relay_.store(true);
        if (relay_thread_.joinable()) {
            relay_thread_.join();
        }
        local_.reset();
        relay_.reset();
        GatewayIntegrationTest::TearDown();
    }

    void start_relay(basecamp::SampleStore* store = nullptr, base::Duration report_period = 1s,
                     std::vector<std::string> uplink = {}, double channel_bps = 0, bool measure_channel = false,
                     basecamp::BackfillArchive* backfill = nullptr) {
        relay_ = std::make_unique<basecamp::Relay>(
            domains_.wan, TestParticipant::wan_qos(domains_.wan_reader_port, domains_.gateway_wan_port), local_domain_,
            fdds::PARTICIPANT_QOS_DEFAULT, store, report_period, std::move(uplink), channel_bps, measure_channel);
        if (backfill != nullptr) {
            relay_->archive_backfill(*backfill);
        }
        relay_thread_ = std::thread([this] { relay_->run(std::chrono::minutes(5), stop_relay_); });
    }

    /// What a robot process offers: reliable, keep last `depth`, transient local or volatile.
    fdds::DataWriterQos writer_qos(bool transient_local, int depth = 100) const {
        fdds::DataWriterQos q = robot_->default_writer_qos();
        q.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
        q.durability().kind = transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
        q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        q.history().depth = depth;
        return q;
    }

    template <typename PubSubType>
    fdds::DataWriter* robot_writer(const std::string& topic, const fdds::DataWriterQos& qos) {
        auto& matches = listener<MatchCounter>();
        auto* writer = robot_->make_writer(topic, fdds::TypeSupport(new PubSubType()), qos, &matches);
        EXPECT_NE(writer, nullptr);
        if (writer != nullptr) {
            EXPECT_TRUE(wait_until([&] { return matches.matched.load() > 0; }, MATCH_TIMEOUT))
                << "the gateway never matched the robot writer of " << topic;
        }
        return writer;
    }

    /// True once the relay's WAN reader matched the gateway's writer of `topic` (within MATCH_TIMEOUT).
    bool relay_matched_gateway_writer(const std::string& topic) {
        return wait_until([&] {
            const auto bridged = gateway_->find_topic(topic);
            return bridged && gateway_->wan_matched_readers(bridged->id) > 0;
        });
    }

    /// A camp tool on the WAN domain, a participant of its own beside the relay.
    std::unique_ptr<TestParticipant> camp_tool() const {
        return std::make_unique<TestParticipant>(
            domains_.wan,
            TestParticipant::wan_qos(base::metatraffic_unicast_port(domains_.wan, 63), domains_.wan_reader_port));
    }

    /// What a ROS 2 tool reads with: reliable.
    static fdds::DataReaderQos reliable_reader_qos(const TestParticipant& participant) {
        fdds::DataReaderQos qos = participant.default_reader_qos();
        qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
        return qos;
    }

    template <typename PubSubType, typename Sample>
    void local_reader(const std::string& topic, const fdds::DataReaderQos& qos, CollectingReader<Sample>& into) {
        ASSERT_NE(local_->make_reader(topic, fdds::TypeSupport(new PubSubType()), qos, &into), nullptr);
    }

    /// A source timestamp a moment ago, as a robot clock gives it.
    static eprosima::fastrtps::Time_t stamp_now() {
        eprosima::fastrtps::Time_t t;
        eprosima::fastrtps::Time_t::now(t);
        return t;
    }

    /// Nanoseconds of a source timestamp as a reader's SampleInfo gives it.
    static std::int64_t ns_of(const eprosima::fastrtps::rtps::Time_t& t) { return t.to_ns(); }
    static std::int64_t ns_of(const eprosima::fastrtps::Time_t& t) { return t.to_ns(); }

    int local_domain_ = 0;
    std::unique_ptr<TestParticipant> local_;
    std::unique_ptr<basecamp::Relay> relay_;
    std::thread relay_thread_;
    std::atomic<bool> stop_relay_{false};
};

}  // namespace tgw::test
