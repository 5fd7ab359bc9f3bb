// telemetry-gateway --uplink (and tm-basecamp relay --uplink): commands from the base camp into the robot domain.
// Real participants with Fast DDS's defaults at both ends (reliable, as ROS 2 has them): a listed topic's fresh
// commands reach the robot with their source timestamps and Lifespan, stale ones never do, and a topic not on the
// list never reaches the robot domain.
#include <gtest/gtest.h>

#include <string>

#include "PaperWorkloadPubSubTypes.h"
#include "test/integration/relay_fixture.hpp"

namespace tgw::test {
namespace {

constexpr const char* ROBOT = "rover1";

using UplinkTest = GatewayIntegrationTest;

/// Whether an uplink's one route has matched both its ends: the writer whose commands its reader takes, and a reader
/// of what it writes.
bool route_matched(const std::vector<passthrough::UplinkCount>& counts) {
    return counts.size() == 1 && counts.front().writers > 0 && counts.front().readers > 0;
}

/// A command numbered `n`, A-sized and filled with its number.
idl::PaperMessage numbered(std::uint64_t n) {
    idl::PaperMessage m;
    m.generated_ns(n);
    m.data(std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(n)));
    return m;
}

/// Writes `fresh` commands numbered from 0, stamped now (their stamps returned), each with a sample on `stray`;
/// then `stale` commands stamped 2 s ago (past a Lifespan of 1 s); then command 99: once it has come, nothing of
/// the others is still on its way.
std::vector<base::WallTime> write_commands(fdds::DataWriter* command, fdds::DataWriter* stray, const base::Clock& clock,
                                           std::uint64_t fresh, std::uint64_t stale) {
    std::vector<base::WallTime> stamps;
    for (std::uint64_t i = 0; i < fresh; ++i) {
        idl::PaperMessage m = numbered(i);
        stamps.push_back(clock.wall_now());
        EXPECT_TRUE(command->write_w_timestamp(&m, fdds::HANDLE_NIL, passthrough::to_dds_time(stamps.back())) ==
                    ReturnCode_t::RETCODE_OK);
        idl::PaperMessage not_listed = numbered(100 + i);
        EXPECT_TRUE(stray->write(&not_listed));
    }
    for (std::uint64_t i = 0; i < stale; ++i) {
        idl::PaperMessage m = numbered(fresh + i);
        EXPECT_TRUE(command->write_w_timestamp(&m, fdds::HANDLE_NIL, passthrough::to_dds_time(clock.wall_now() - 2s)) ==
                    ReturnCode_t::RETCODE_OK);
    }
    idl::PaperMessage last = numbered(99);
    EXPECT_TRUE(command->write(&last));
    return stamps;
}

TEST_F(UplinkTest, ListedCommandsReachTheRobotFreshAndNothingElseDoes) {
    const std::string command = topic_prefix_ + "cmd_vel";
    const std::string other = topic_prefix_ + "other";
    GatewayConfig c = config();
    c.robot_name = ROBOT;
    c.uplink = {command};
    start_gateway(c);

    // A robot program with Fast DDS's default participant and readers, of the listed topic and of another one.
    PublisherWatcher offered;
    TestParticipant robot_program(domains_.robot, TestParticipant::robot_qos(), &offered);
    ASSERT_TRUE(robot_program.ok());
    auto& commands = listener<CollectingReader<idl::PaperMessage>>();
    auto& others = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_NE(robot_program.make_reader(command, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                        robot_program.default_reader_qos(), &commands),
              nullptr);
    ASSERT_NE(robot_program.make_reader(other, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                        robot_program.default_reader_qos(), &others),
              nullptr);

    // The base camp publishes both under the robot's name, with a writer's defaults and a Lifespan of 1 s.
    fdds::DataWriterQos qos = basecamp_->default_writer_qos();
    qos.lifespan().duration = passthrough::to_dds_duration(1s);
    auto& command_matches = listener<MatchCounter>();
    auto* command_writer =
        basecamp_->make_writer(std::string(ROBOT) + "/" + command, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                               qos, &command_matches);
    auto* other_writer = basecamp_->make_writer(std::string(ROBOT) + "/" + other,
                                                fdds::TypeSupport(new idl::PaperMessagePubSubType()), qos);
    ASSERT_NE(command_writer, nullptr);
    ASSERT_NE(other_writer, nullptr);
    // Both sides of each match: a writer that has matched a reader the reader has not matched yet sends what the
    // reader drops, and with a Lifespan of 1 s the repairs may come too late under load (CI: 0 of 11 came).
    ASSERT_TRUE(wait_until(
        [&] {
            return commands.matched.load() > 0 && command_matches.matched.load() > 0 &&
                   route_matched(gateway_->uplink_counts());
        },
        MATCH_TIMEOUT))
        << "the uplink of " << command << " never matched both ends";

    // The gateway offers the robot what the base camp offered, with the command's Lifespan.
    PublisherWatcher::Seen seen;
    ASSERT_TRUE(wait_until([&] { return offered.find(command, seen); }, MATCH_TIMEOUT));
    EXPECT_EQ(seen.reliability, fdds::RELIABLE_RELIABILITY_QOS);
    EXPECT_EQ(seen.lifespan, passthrough::to_dds_duration(1s));

    // Fresh commands arrive whole, with the base camp's source timestamps; stale ones (2 s old, Lifespan 1 s) never
    // do; a fresh one after them shows that nothing of them was still on its way.
    constexpr std::uint64_t FRESH = 10;
    constexpr std::uint64_t STALE = 5;
    const std::uint64_t unscheduled_before = gateway_->unscheduled_wire_bytes();
    const std::vector<base::WallTime> stamps = write_commands(command_writer, other_writer, clock_, FRESH, STALE);
    ASSERT_TRUE(wait_until([&] { return commands.count() >= FRESH + 1; })) << commands.count() << " commands came";

    const auto received = commands.received();
    ASSERT_EQ(received.size(), FRESH + 1);
    for (std::uint64_t i = 0; i < FRESH; ++i) {
        EXPECT_EQ(received[i].data.generated_ns(), i);
        EXPECT_EQ(received[i].data.data(), std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
        EXPECT_EQ(received[i].info.source_timestamp.to_ns(), base::to_ns(stamps[i]));
    }
    EXPECT_EQ(received.back().data.generated_ns(), 99u);

    // Nothing of the topic not listed reached the robot domain: no writer of it there, not a sample.
    EXPECT_EQ(others.matched.load(), 0);
    EXPECT_EQ(others.count(), 0u);
    EXPECT_FALSE(offered.find(other, seen));
    EXPECT_FALSE(offered.find(std::string(ROBOT) + "/" + other, seen));

    const std::vector<passthrough::UplinkCount> counts = gateway_->uplink_counts();
    ASSERT_EQ(counts.size(), 1u);
    const passthrough::UplinkCount& up = counts.front();
    EXPECT_EQ(up.from_topic, std::string(ROBOT) + "/" + command);
    EXPECT_EQ(up.to_topic, command);
    ASSERT_TRUE(up.ttl);
    EXPECT_EQ(up.ttl->ttl, 1s);
    EXPECT_EQ(up.ttl->source, passthrough::TtlSource::publisher);
    EXPECT_EQ(up.received, FRESH + STALE + 1);
    EXPECT_EQ(up.delivered, FRESH + 1);
    EXPECT_EQ(up.expired, STALE);
    EXPECT_EQ(up.failed, 0u);
    // Each charged to the link budget at its size on the wire.
    idl::PaperMessagePubSubType type;
    idl::PaperMessage sample = numbered(0);
    eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&sample)());
    ASSERT_TRUE(type.serialize(&sample, &payload));
    EXPECT_EQ(up.wire_bytes, (FRESH + STALE + 1) * c.scheduler.wire.wire_bytes(payload.length));
    // ...as traffic outside the schedule (--duplex half, the default), which the status tells the base camp's
    // grantor: a robot's share then leaves room for its commands.
    EXPECT_GE(gateway_->unscheduled_wire_bytes() - unscheduled_before, up.wire_bytes);
}

using UplinkRelayTest = RelayTest;

// A camp program on the camp's own domain, with Fast DDS's defaults: the relay carries its commands onto the WAN,
// and drops the stale ones before they cost the link.
TEST_F(UplinkRelayTest, ACampProgramsCommandsReachTheRobotThroughTheRelay) {
    const std::string command = topic_prefix_ + "cmd_vel";
    const std::string other = topic_prefix_ + "other";
    const std::string camp_command = std::string(ROBOT) + "/" + command;
    const std::string camp_other = std::string(ROBOT) + "/" + other;
    GatewayConfig c = config();
    c.robot_name = ROBOT;
    c.uplink = {command, other};  // the gateway would take both: the relay carries only the one it lists
    start_gateway(c);
    start_relay(nullptr, 1s, {camp_command});

    auto& commands = listener<CollectingReader<idl::PaperMessage>>();
    auto& others = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_NE(robot_->make_reader(command, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                  robot_->default_reader_qos(), &commands),
              nullptr);
    ASSERT_NE(robot_->make_reader(other, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                  robot_->default_reader_qos(), &others),
              nullptr);
    fdds::DataWriterQos qos = local_->default_writer_qos();
    qos.lifespan().duration = passthrough::to_dds_duration(1s);
    auto& command_matches = listener<MatchCounter>();
    auto& other_matches = listener<MatchCounter>();
    auto* command_writer =
        local_->make_writer(camp_command, fdds::TypeSupport(new idl::PaperMessagePubSubType()), qos, &command_matches);
    auto* other_writer =
        local_->make_writer(camp_other, fdds::TypeSupport(new idl::PaperMessagePubSubType()), qos, &other_matches);
    ASSERT_NE(command_writer, nullptr);
    ASSERT_NE(other_writer, nullptr);
    ASSERT_TRUE(wait_until(
        [&] {
            return command_matches.matched.load() > 0 && route_matched(relay_->uplink_counts()) &&
                   route_matched(gateway_->uplink_counts()) && commands.matched.load() > 0;
        },
        3 * MATCH_TIMEOUT))
        << "the relay's and the gateway's uplinks of " << camp_command << " never matched";

    constexpr std::uint64_t FRESH = 10;
    constexpr std::uint64_t STALE = 5;
    write_commands(command_writer, other_writer, clock_, FRESH, STALE);
    ASSERT_TRUE(wait_until([&] { return commands.count() >= FRESH + 1; })) << commands.count() << " commands came";

    const auto received = commands.received();
    ASSERT_EQ(received.size(), FRESH + 1);
    for (std::uint64_t i = 0; i < FRESH; ++i) {
        EXPECT_EQ(received[i].data.generated_ns(), i);
    }
    EXPECT_EQ(received.back().data.generated_ns(), 99u);
    EXPECT_EQ(other_matches.matched.load(), 0) << "the relay read a topic it does not carry";
    EXPECT_EQ(others.count(), 0u);

    const auto relay_counts = relay_->uplink_counts();
    ASSERT_EQ(relay_counts.size(), 1u);
    EXPECT_EQ(relay_counts.front().from_topic, camp_command);
    EXPECT_EQ(relay_counts.front().received, FRESH + STALE + 1);
    EXPECT_EQ(relay_counts.front().delivered, FRESH + 1);
    EXPECT_EQ(relay_counts.front().expired, STALE);
    const auto gateway_counts = gateway_->uplink_counts();
    ASSERT_EQ(gateway_counts.size(), 1u) << "the gateway discovered a WAN writer of " << camp_other;
    EXPECT_EQ(gateway_counts.front().received, FRESH + 1);
    EXPECT_EQ(gateway_counts.front().delivered, FRESH + 1);
}

}  // namespace
}  // namespace tgw::test
