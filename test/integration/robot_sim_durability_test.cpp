// tm-robot-sim's writers (PaperPublisher) with --transient-local keep what they wrote for a reader that joins later,
// as Fast DDS's default writer does (a transient-local reader matches no volatile writer, tm-robot-sim's default).
// Real participants on the test's robot domain.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <numeric>
#include <vector>

#include "PaperWorkload.h"
#include "PaperWorkloadPubSubTypes.h"
#include "gateway/apps/tm_robot_sim/paper_publisher.hpp"
#include "test/integration/dds_test_support.hpp"

namespace tgw::test {
namespace {

using namespace std::chrono_literals;

TEST(RobotSimDurabilityTest, TransientLocalWritersGiveALateReaderWhatTheyKept) {
    // Published for 0.5 s at 20 Hz with a TTL of 10 s, before any reader exists.
    const TestDomains domains = TestDomains::for_this_process();
    const core::MessageStream stream{"L", "sim/late_joiner", 100, std::chrono::seconds(10), 20.0};
    robot_sim::PaperPublisher publisher(domains.robot, {stream}, base::PeerTransport{},
                                        robot_sim::WriterDurability::transient_local);
    const std::atomic<bool> stop{false};
    const std::uint64_t written = publisher.run(500ms, stop).at(0).written;
    EXPECT_GE(written, 9u);

    TestParticipant late(domains.robot, TestParticipant::robot_qos());
    ASSERT_TRUE(late.ok());
    fdds::DataReaderQos qos = late.default_reader_qos();
    qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    qos.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
    CollectingReader<idl::PaperMessage> collector;
    fdds::DataReader* reader =
        late.make_reader(stream.topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()), qos, &collector);
    ASSERT_NE(reader, nullptr);
    EXPECT_TRUE(wait_until([&] { return collector.matched.load() > 0; }));
    wait_until([&] { return collector.count() >= written; }, 5000ms);
    reader->set_listener(nullptr);

    // The history holds what the TTL keeps alive: every sample, in order.
    std::vector<std::uint32_t> taken;
    for (const auto& r : collector.received()) {
        taken.push_back(r.data.sequence_number());
    }
    std::vector<std::uint32_t> expected(written);
    std::iota(expected.begin(), expected.end(), 0u);
    EXPECT_EQ(taken, expected);
}

}  // namespace
}  // namespace tgw::test
