// telemetry-gateway --robot-name: a fleet's robots kept apart on the WAN. Real participants: the robot's topics
// reach base-camp readers of the namespaced names (directly in standard mode, through the relay in compact mode),
// and nothing is published under the robot's own names.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <string>

#include "PaperWorkloadPubSubTypes.h"
#include "RosStringPubSubTypes.h"
#include "test/integration/relay_fixture.hpp"

namespace tgw::test {
namespace {

constexpr const char* ROBOT = "rover1";

/// The topic names in the on-robot log's `table`, sorted and distinct.
std::vector<std::string> logged_topics(const std::string& log_file, const std::string& table) {
    std::vector<std::string> topics;
    sqlite3* db = nullptr;
    if (sqlite3_open_v2(log_file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
        ADD_FAILURE() << "cannot open " << log_file;
        sqlite3_close(db);
        return topics;
    }
    sqlite3_stmt* stmt = nullptr;
    const std::string sql = "SELECT DISTINCT topic FROM " + table + " ORDER BY topic";
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr) == SQLITE_OK) {
        while (sqlite3_step(stmt) == SQLITE_ROW) {
            topics.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0)));
        }
    } else {
        ADD_FAILURE() << sql << ": " << sqlite3_errmsg(db);
    }
    sqlite3_finalize(stmt);
    sqlite3_close(db);
    return topics;
}

/// Writes PaperMessages 0 to n - 1, each A-sized and filled with its number.
void write_numbered(fdds::DataWriter* writer, std::uint64_t n) {
    for (std::uint64_t i = 0; i < n; ++i) {
        idl::PaperMessage m;
        m.generated_ns(i);
        m.data(std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
        ASSERT_TRUE(writer->write(&m));
    }
}

using RobotNameTest = GatewayIntegrationTest;

TEST_F(RobotNameTest, TheBaseCampReadsTheRobotsTopicsUnderItsName) {
    GatewayConfig c = config();
    c.robot_name = ROBOT;
    c.log_file = temp_file(".db");
    start_gateway(c);

    // A ROS 2 topic gets the name after rt/, any other topic in front.
    auto& chatter = listener<CollectingReader<std_msgs::msg::dds_::String_>>();
    auto* ros_writer = bridge<std_msgs::msg::dds_::String_PubSubType>("rt/chatter", robot_writer_qos(*robot_), chatter,
                                                                      nullptr, "rt/rover1/chatter");
    ASSERT_NE(ros_writer, nullptr);
    const std::string topic = topic_prefix_ + "telemetry";
    const std::string wan_topic = std::string(ROBOT) + "/" + topic;
    auto& telemetry = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), telemetry, nullptr, wan_topic);
    ASSERT_NE(writer, nullptr);
    // A base-camp reader of the robot's own name: no writer of it on the WAN.
    auto& unnamed = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_NE(basecamp_->make_reader(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                     wan_reader_qos(*basecamp_), &unnamed),
              nullptr);

    std_msgs::msg::dds_::String_ hello;
    hello.data("hello from rover1");
    ASSERT_TRUE(ros_writer->write(&hello));
    constexpr std::uint64_t N = 10;
    write_numbered(writer, N);
    ASSERT_TRUE(wait_until([&] { return chatter.count() >= 1 && telemetry.count() >= N; }));
    EXPECT_EQ(chatter.received().front().data.data(), "hello from rover1");
    for (std::uint64_t i = 0; i < N; ++i) {
        EXPECT_EQ(telemetry.received()[i].data.generated_ns(), i);
    }
    EXPECT_EQ(unnamed.matched.load(), 0);
    EXPECT_EQ(unnamed.count(), 0u);
    // The gateway still knows the topics by the robot's names (allow, deny, --qos profiles go by them).
    EXPECT_TRUE(gateway_->find_topic("rt/chatter"));
    EXPECT_TRUE(gateway_->find_topic(topic));

    // The on-robot log names them as the base camp records them, so that report and merge match its rows.
    gateway_->stop();
    EXPECT_EQ(logged_topics(c.log_file, "forwarded_samples"),
              (std::vector<std::string>{wan_topic, "rt/rover1/chatter"}));
}

using RobotNameCompactTest = RelayTest;

TEST_F(RobotNameCompactTest, TheRelayRepublishesTheRobotsTopicsUnderItsName) {
    GatewayConfig c = config();
    c.compact_wan = true;
    c.robot_name = ROBOT;
    start_gateway(c);
    start_relay();
    const std::string topic = topic_prefix_ + "telemetry";
    const std::string camp_topic = std::string(ROBOT) + "/" + topic;

    // Fast DDS's defaults on the camp's domain, as any tool there has them.
    auto& reader = listener<CollectingReader<idl::PaperMessage>>();
    local_reader<idl::PaperMessagePubSubType>(camp_topic, local_->default_reader_qos(), reader);
    auto* writer = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(false));
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(wait_until([&] { return reader.matched.load() > 0; }, 3 * MATCH_TIMEOUT))
        << "the relay never republished " << camp_topic;
    ASSERT_TRUE(wait_until([&] { return relay_->local_readers(camp_topic) > 0; }, MATCH_TIMEOUT));
    EXPECT_EQ(relay_->local_readers(topic), 0) << "nothing goes out under the robot's own name";
    ASSERT_TRUE(
        wait_until([&] { return gateway_->wan_matched_readers(gateway_->find_topic(topic)->id) > 0; }, MATCH_TIMEOUT));

    constexpr std::uint64_t N = 10;
    write_numbered(writer, N);
    ASSERT_TRUE(wait_until([&] { return reader.count() >= N; }));
    for (std::uint64_t i = 0; i < N; ++i) {
        EXPECT_EQ(reader.received()[i].data.generated_ns(), i);
        EXPECT_EQ(reader.received()[i].data.data(), std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
    }
}

}  // namespace
}  // namespace tgw::test
