// tm-robot-sim's writers (PaperPublisher) with --transient-local keep what they wrote for a reader that joins later,
// as Fast DDS's default writer does (a transient-local reader matches no volatile writer, tm-robot-sim's default).
// Real participants on the test's robot domain.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <numeric>
#include <vector>

#include "PaperWorkload.h"
#include "PaperWorkloadPubSubTypes.h"
#include "gateway/apps/tm_robot_sim/paper_publisher.hpp"
#include "test/integration/dds_test_support.hpp"

namespace tgw::test {
namespace {

using namespace std::chrono_literals;
using robot_sim::WriterDurability;

/// Collects the sequence numbers a reader takes.
class SequenceCollector final : public fdds::DataReaderListener {
  public:
    void on_data_available(fdds::DataReader* reader) override {
        idl::PaperMessage message;
        fdds::SampleInfo info;
        while (reader->take_next_sample(&message, &info) == ReturnCode_t::RETCODE_OK) {
            if (info.valid_data) {
                std::lock_guard<std::mutex> lock(mutex_);
                sequences_.push_back(message.sequence_number());
            }
        }
    }
    std::vector<std::uint32_t> sequences() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return sequences_;
    }

  private:
    mutable std::mutex mutex_;
    std::vector<std::uint32_t> sequences_;
};

class RobotSimDurabilityTest : public ::testing::Test {
  protected:
    /// Publishes for 0.5 s at 20 Hz (TTL 10 s) with `durability`, then starts a reliable, transient-local reader and
    /// returns what it took within `wait` after matching the writer. `written_`: how many were published.
    std::vector<std::uint32_t> late_reader_takes(WriterDurability durability, std::chrono::milliseconds wait) {
        const TestDomains domains = TestDomains::for_this_process();
        const core::MessageStream stream{"L", "sim/late_joiner", 100, std::chrono::seconds(10), 20.0};
        robot_sim::PaperPublisher publisher(domains.robot, {stream}, base::PeerTransport{}, durability);
        const std::atomic<bool> stop{false};
        const std::vector<robot_sim::StreamReport> reports = publisher.run(500ms, stop);
        written_ = reports.at(0).written;
        EXPECT_GE(written_, 9u);

        TestParticipant late(domains.robot, TestParticipant::robot_qos());
        EXPECT_TRUE(late.ok());
        fdds::DataReaderQos qos = late.default_reader_qos();
        qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
        qos.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
        SequenceCollector collector;
        fdds::DataReader* reader =
            late.make_reader(stream.topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()), qos, &collector);
        EXPECT_NE(reader, nullptr);
        if (reader == nullptr) {
            return {};
        }
        EXPECT_TRUE(wait_until([&] {
            fdds::SubscriptionMatchedStatus status;
            reader->get_subscription_matched_status(status);
            return status.current_count > 0;
        }));
        wait_until([&] { return collector.sequences().size() >= written_; }, wait);
        reader->set_listener(nullptr);
        return collector.sequences();
    }

    std::uint64_t written_ = 0;
};

TEST_F(RobotSimDurabilityTest, TransientLocalWritersGiveALateReaderWhatTheyKept) {
    const std::vector<std::uint32_t> taken = late_reader_takes(WriterDurability::transient_local, 5000ms);
    // The history holds what the TTL keeps alive: every sample, in order.
    std::vector<std::uint32_t> expected(written_);
    std::iota(expected.begin(), expected.end(), 0u);
    EXPECT_EQ(taken, expected);
}

}  // namespace
}  // namespace tgw::test
