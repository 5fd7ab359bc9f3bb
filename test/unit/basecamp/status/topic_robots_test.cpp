// The robot of each topic at the base camp, from the gateways' status: TopicRobots itself, and the robot column
// of `tm-basecamp report`, `stats` and the status view for a fleet (and its absence for a single unnamed robot).
#include "basecamp/status/topic_robots.hpp"

#include <gtest/gtest.h>

#include <iterator>
#include <sstream>

#include "basecamp/analysis/report.hpp"
#include "basecamp/live/status_view.hpp"
#include "basecamp/live/topic_stats.hpp"
#include "test/unit/basecamp/recording_file.hpp"
#include "test/unit/basecamp/scratch_dir.hpp"
#include "test/unit/basecamp/status_samples.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {
namespace {

constexpr std::int64_t MS = 1'000'000;
constexpr std::int64_t T0 = 1'700'000'000'000 * MS;

/// The status of gateway `gateway` of robot `robot` (empty: unnamed), bridging `topics`, as the base camp
/// receives it.
SampleRecord status_of(std::uint8_t gateway, const std::string& robot, const std::vector<std::string>& topics,
                       std::int64_t receive_ns = T0) {
    idl::GatewayStatus status;
    status.gateway_prefix()[0] = gateway;
    status.robot_name(robot);
    status.sent_ns(static_cast<std::uint64_t>(receive_ns - 100 * MS));
    status.sensed_rate_bps(20'000);
    for (const std::string& topic : topics) {
        status.topics().push_back(test::topic_status(topic, 1000, 10, 0));
    }
    SampleRecord r;
    r.topic = wire::STATUS_TOPIC;
    r.type_name = "tgw::idl::GatewayStatus";
    r.source_ns = receive_ns - 100 * MS;
    r.receive_ns = receive_ns;
    r.payload = test::serialized(status);
    return r;
}

SampleRecord sample_of(const std::string& topic, std::int64_t receive_ns) {
    SampleRecord r;
    r.topic = topic;
    r.type_name = "tgw::idl::PaperMessage";
    r.source_ns = receive_ns - 200 * MS;
    r.receive_ns = receive_ns;
    r.payload.assign(45, 0);
    return r;
}

std::vector<std::string> fields_of(const std::string& line) {
    std::istringstream in(line);
    return {std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
}

/// The fields of the line of `text` that starts with `first`, or nothing.
std::vector<std::string> row_of(const std::string& text, const std::string& first) {
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        std::vector<std::string> f = fields_of(line);
        if (!f.empty() && f[0] == first) {
            return f;
        }
    }
    return {};
}

TEST(TopicRobotsTest, NamesTheRobotWhoseGatewayBridgesEachTopic) {
    TopicRobots robots;
    robots.add(status_of(1, "rover1", {"rover1/telemetry/A", "rt/rover1/odom"}));
    robots.add(status_of(2, "rover2", {"rover2/telemetry/A"}));
    robots.add(status_of(3, "", {"telemetry/A"}));  // a gateway without --robot-name
    robots.add(sample_of("rover3/telemetry/A", T0));

    EXPECT_EQ(robots.robot_of("rover1/telemetry/A"), "rover1");
    EXPECT_EQ(robots.robot_of("rt/rover1/odom"), "rover1");
    EXPECT_EQ(robots.robot_of("rover2/telemetry/A"), "rover2");
    EXPECT_EQ(robots.robot_of("telemetry/A"), "") << "an unnamed robot";
    EXPECT_EQ(robots.robot_of("rover3/telemetry/A"), "") << "no status names it: the topic's name is not a guess";
    EXPECT_EQ(robots.robot_of(wire::STATUS_TOPIC), "") << "every gateway's";
    EXPECT_TRUE(robots.any());
}

TEST(TopicRobotsTest, AnUndecodableStatusTeachesNothing) {
    TopicRobots robots;
    SampleRecord bad = status_of(1, "rover1", {"rover1/telemetry/A"});
    bad.payload.resize(bad.payload.size() / 2);
    robots.add(bad);
    EXPECT_FALSE(robots.any());
}

TEST(TopicRobotsTest, TheStatsTableHasARobotColumnForAFleetOnly) {
    TopicStats fleet(std::chrono::seconds(10));
    fleet.add(status_of(1, "rover1", {"rover1/telemetry/A"}));
    fleet.add(status_of(2, "rover2", {"rover2/telemetry/A"}));
    fleet.add(sample_of("rover1/telemetry/A", T0 + 100 * MS));
    fleet.add(sample_of("rover2/telemetry/A", T0 + 150 * MS));
    std::ostringstream out;
    print_stats_table(out, fleet.rows(T0 + 200 * MS));
    EXPECT_EQ(fields_of(out.str().substr(0, out.str().find('\n'))).back(), "robot") << out.str();
    EXPECT_EQ(row_of(out.str(), "rover1/telemetry/A").back(), "rover1") << out.str();
    EXPECT_EQ(row_of(out.str(), "rover2/telemetry/A").back(), "rover2") << out.str();
    EXPECT_EQ(row_of(out.str(), wire::STATUS_TOPIC).back(), "-") << out.str();

    TopicStats single(std::chrono::seconds(10));
    single.add(status_of(1, "", {"telemetry/A"}));
    single.add(sample_of("telemetry/A", T0 + 100 * MS));
    std::ostringstream plain;
    print_stats_table(plain, single.rows(T0 + 200 * MS));
    EXPECT_EQ(plain.str().find("robot"), std::string::npos) << plain.str();
    EXPECT_EQ(row_of(plain.str(), "telemetry/A").size(), 9u) << plain.str();
}

TEST(TopicRobotsTest, TheStatusViewNamesEachGatewaysRobotInRobotOrder) {
    StatusView view(std::chrono::minutes(1));
    view.add(status_of(1, "rover2", {"rover2/telemetry/A"}));
    view.add(status_of(2, "rover1", {"rover1/telemetry/A"}));
    std::ostringstream out;
    view.render(out, T0 + 1000 * MS);
    const std::string screen = out.str();
    const auto rover1 = screen.find("robot rover1, gateway 02.");
    const auto rover2 = screen.find("robot rover2, gateway 01.");
    ASSERT_NE(rover1, std::string::npos) << screen;
    ASSERT_NE(rover2, std::string::npos) << screen;
    EXPECT_LT(rover1, rover2) << screen;
}

class ReportRobotsTest : public ::testing::Test {
  protected:
    void SetUp() override { recording_ = dir_.file("record.db"); }

    std::string printed(const std::vector<SampleRecord>& samples) {
        test::write_recording(recording_, {}, samples);
        std::ostringstream out;
        print_report(out, read_report(recording_, ReportOptions{}));
        return out.str();
    }

    test::ScratchDir dir_{"tgw-report-robots"};
    std::string recording_;
};

TEST_F(ReportRobotsTest, ARecordingOfAFleetReportsEachTopicsRobot) {
    const std::vector<SampleRecord> samples = {
        sample_of("rover1/telemetry/A", T0),  // before rover1's first status: the recording's statuses all count
        status_of(1, "rover1", {"rover1/telemetry/A"}, T0 + 500 * MS),
        status_of(2, "rover2", {"rover2/telemetry/A"}, T0 + 600 * MS),
        sample_of("rover2/telemetry/A", T0 + 700 * MS),
    };
    const std::string text = printed(samples);
    const std::vector<std::string> header = fields_of(text.substr(0, text.find('\n')));
    ASSERT_FALSE(header.empty());
    EXPECT_EQ(header.back(), "robot") << text;
    EXPECT_EQ(row_of(text, "rover1/telemetry/A").size(), 10u) << text;
    EXPECT_EQ(row_of(text, "rover1/telemetry/A").back(), "rover1") << text;
    EXPECT_EQ(row_of(text, "rover2/telemetry/A").back(), "rover2") << text;
    EXPECT_EQ(row_of(text, wire::STATUS_TOPIC).back(), "-") << text;
}

TEST_F(ReportRobotsTest, ASingleUnnamedRobotsReportKeepsItsNineColumns) {
    const std::string text = printed({status_of(1, "", {"telemetry/A"}, T0), sample_of("telemetry/A", T0 + MS)});
    EXPECT_EQ(text.substr(0, text.find('\n')).find("robot"), std::string::npos) << text;
    EXPECT_EQ(row_of(text, "telemetry/A").size(), 9u) << text;
}

}  // namespace
}  // namespace tgw::basecamp
