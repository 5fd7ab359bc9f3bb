// A fleet's shared channel (tm-basecamp relay --channel-rate, telemetry-gateway --channel-grants), with real
// participants: two gateways whose sensors each see the whole radio, and the relay that grants them shares of one
// 30,000 bit/s channel from their statuses. rover1 has hazards to send (TTL 1 s), rover2 a bulk topic (TTL 20 s):
// rover1 gets what its hazards need, rover2 the rest, where equal shares would give each half.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "ChannelGrantPubSubTypes.h"
#include "PaperWorkloadPubSubTypes.h"
#include "basecamp/recording/sample_store.hpp"
#include "core/granted_rate.hpp"
#include "passthrough/dds_time.hpp"
#include "test/integration/relay_fixture.hpp"
#include "wire/channel_grant_topic.hpp"

namespace tgw::test {
namespace {

constexpr double CHANNEL_BPS = 30'000;

// Two gateways with --channel-grants on one 30,000 bit/s channel, rover1 for hazards (TTL 1 s), rover2 for a bulk
// topic (TTL 20 s), each publisher at 20 Hz once started: rover1's 41-byte hazards need about 38,000 bit/s on the
// wire, rover2's kilobyte samples more.
class ChannelGrantTest : public RelayTest {
  protected:
    void SetUp() override {
        RelayTest::SetUp();
        GatewayConfig c1 = config();
        c1.robot_name = "rover1";
        c1.allow = {topic_prefix_ + "hazards"};
        c1.channel_grants = true;
        c1.status_period = 1s;
        c1.uplink = {topic_prefix_ + "cmd_vel"};  // --duplex half: its budget pays for the camp's commands
        GatewayConfig c2 = c1;
        c2.robot_name = "rover2";
        c2.uplink = {};
        c2.allow = {topic_prefix_ + "bulk"};
        c2.wan_port = base::metatraffic_unicast_port(domains_.wan, 62);
        start_gateway(c1);
        rover2_ = std::make_unique<Gateway>(c2, clock_);
        store_path_ = temp_file(".db");
        store_ = std::make_unique<basecamp::SampleStore>(store_path_, "--out", 50);
        start_relay(store_.get(), 1s, {camp_command()}, CHANNEL_BPS);
    }

    /// rover1's command topic at the camp, which the relay carries (relay --uplink).
    std::string camp_command() const { return "rover1/" + topic_prefix_ + "cmd_vel"; }

    void TearDown() override {
        stop_publishing();
        rover2_.reset();
        RelayTest::TearDown();
    }

    /// Starts writing `topic`'s samples of `bytes` with a Lifespan of `ttl`, at 20 Hz, until TearDown.
    void publish(const std::string& topic, base::Duration ttl, std::size_t bytes) {
        auto* writer = robot_writer<idl::PaperMessagePubSubType>(topic_prefix_ + topic, robot_writer_qos(*robot_, ttl));
        ASSERT_NE(writer, nullptr);
        publishers_.emplace_back([this, writer, bytes] {
            for (std::uint32_t i = 0; !stop_.load(); ++i) {
                idl::PaperMessage sample;
                sample.sequence_number(i);
                sample.data(std::vector<std::uint8_t>(bytes, 1));
                writer->write(&sample);
                std::this_thread::sleep_for(50ms);
            }
        });
    }

    void stop_publishing() {
        stop_.store(true);
        for (std::thread& t : publishers_)
            t.join();
        publishers_.clear();
    }

    /// Waits up to `timeout` for rover1's grant above 20,000 bit/s and rover2's below 10,000.
    ::testing::AssertionResult hazards_granted_first(std::chrono::milliseconds timeout) {
        const bool ok = wait_until(
            [&] {
                const auto g1 = gateway_->granted_bps();
                const auto g2 = rover2_->granted_bps();
                return g1 && g2 && *g1 > 20'000 && *g2 < 10'000;
            },
            timeout);
        if (ok)
            return ::testing::AssertionSuccess();
        return ::testing::AssertionFailure() << "grants: rover1 " << gateway_->granted_bps().value_or(-1) << ", rover2 "
                                             << rover2_->granted_bps().value_or(-1) << " bit/s";
    }

    /// rover2 publishes bulk, rover1 nothing: waits up to 30 s for rover1's grant below 6,000 bit/s (its least
    /// share) and rover2's above 20,000.
    ::testing::AssertionResult rover1_idle_at_its_least_share() {
        publish("bulk", 20s, 1016);
        const bool ok = wait_until(
            [&] {
                const auto g1 = gateway_->granted_bps();
                const auto g2 = rover2_->granted_bps();
                return g1 && g2 && *g1 < 6'000 && *g2 > 20'000;
            },
            30s);
        if (ok)
            return ::testing::AssertionSuccess();
        return ::testing::AssertionFailure() << "grants: rover1 " << gateway_->granted_bps().value_or(-1) << ", rover2 "
                                             << rover2_->granted_bps().value_or(-1) << " bit/s";
    }

    /// rover1 publishes hazards and rover2 bulk, and go on until TearDown, so that the next round of grants is
    /// made from the same demand; waits for hazards_granted_first (30 s at most).
    ::testing::AssertionResult both_publishing_hazards_granted_first() {
        publish("hazards", 1s, 41);
        publish("bulk", 20s, 1016);
        return hazards_granted_first(30s);
    }

    std::unique_ptr<Gateway> rover2_;
    std::string store_path_;
    std::unique_ptr<basecamp::SampleStore> store_;  ///< the relay's recording; outlives it (RelayTest::TearDown)
    std::atomic<bool> stop_{false};
    std::vector<std::thread> publishers_;
};

TEST_F(ChannelGrantTest, TheRobotWithUrgentSamplesGetsTheirShareFirst) {
    ASSERT_TRUE(both_publishing_hazards_granted_first());

    // Each gateway budgets for its grant (its sensor, 50 Mbit/s, sees the whole radio), and together no more than
    // the channel.
    const double rate1 = gateway_->rate_bps();
    const double rate2 = rover2_->rate_bps();
    EXPECT_GT(rate1, 20'000);
    EXPECT_LT(rate2, 10'000);
    EXPECT_LE(rate1 + rate2, CHANNEL_BPS * 1.001);
    const core::ChannelGrants grants = relay_->channel_grants();
    ASSERT_EQ(grants.size(), 2u);
    double total = 0;
    for (const auto& [gateway, bps] : grants)
        total += bps;
    EXPECT_LE(total, CHANNEL_BPS * 1.001);
}

// The relay's recording keeps every round of grants, each gateway's under its robot's name: what a robot was granted
// is there to read beside what arrived of it.
TEST_F(ChannelGrantTest, TheCampRecordsEachRoundOfGrantsUnderTheRobotsNames) {
    ASSERT_TRUE(both_publishing_hazards_granted_first());
    stop_relay_.store(true);  // no round after the last one read here
    relay_thread_.join();
    const core::ChannelGrants last = relay_->channel_grants();
    store_->flush();

    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open_v2(store_path_.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
    const auto query = [&](const std::string& sql, const std::function<void(sqlite3_stmt*)>& row) {
        sqlite3_stmt* stmt = nullptr;
        ASSERT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
        while (sqlite3_step(stmt) == SQLITE_ROW)
            row(stmt);
        sqlite3_finalize(stmt);
    };
    // A round a second at least (and at once when a status comes), the channel as told, nothing measured.
    std::int64_t rounds = 0;
    query("SELECT COUNT(*), MIN(channel_bps), MAX(channel_bps), COUNT(verdict), MIN(newcomer_bps) FROM channel",
          [&](sqlite3_stmt* row) {
              rounds = sqlite3_column_int64(row, 0);
              EXPECT_EQ(sqlite3_column_double(row, 1), CHANNEL_BPS);
              EXPECT_EQ(sqlite3_column_double(row, 2), CHANNEL_BPS);
              EXPECT_EQ(sqlite3_column_int64(row, 3), 0) << "a verdict where the channel is not measured";
              EXPECT_NEAR(sqlite3_column_double(row, 4), core::JOIN_SHARE * CHANNEL_BPS, 1e-6);
          });
    EXPECT_GE(rounds, 2);
    // Each robot's newest grant is the one the relay last wrote to its gateway, and no round grants more than the
    // channel. Grants move from round to round (CI saw a last round give rover1 18,815 bit/s), so the round that
    // granted hazards first is looked for among all of them, not taken to be the last.
    std::map<std::string, std::pair<std::string, double>> newest;  // robot: its gateway and its grant
    std::map<std::int64_t, std::map<std::string, double>> rounds_by_time;
    query("SELECT robot, gateway, rate_bps, time_ns FROM grants ORDER BY time_ns", [&](sqlite3_stmt* row) {
        const auto* robot = reinterpret_cast<const char*>(sqlite3_column_text(row, 0));
        const auto* gateway = reinterpret_cast<const char*>(sqlite3_column_text(row, 1));
        ASSERT_NE(robot, nullptr) << "a grant without its robot's name";
        ASSERT_NE(gateway, nullptr);
        const double bps = sqlite3_column_double(row, 2);
        rounds_by_time[sqlite3_column_int64(row, 3)][robot] = bps;
        if (last.count(gateway) != 0)
            newest[robot] = {gateway, bps};
    });
    query("SELECT MAX(total) FROM (SELECT SUM(rate_bps) AS total FROM grants GROUP BY time_ns)",
          [&](sqlite3_stmt* row) { EXPECT_LE(sqlite3_column_double(row, 0), CHANNEL_BPS * 1.001); });
    sqlite3_close(db);
    ASSERT_EQ(newest.size(), 2u) << "rover1's and rover2's grants";
    for (const auto& [robot, grant] : newest)
        EXPECT_NEAR(grant.second, last.at(grant.first), 1e-6) << robot << "'s newest grant is not the relay's last";
    const bool hazards_first_recorded =
        std::any_of(rounds_by_time.begin(), rounds_by_time.end(), [](const auto& round) {
            const auto& grants = round.second;
            return grants.count("rover1") != 0 && grants.count("rover2") != 0 && grants.at("rover1") > 20'000 &&
                   grants.at("rover2") < 10'000;
        });
    EXPECT_TRUE(hazards_first_recorded) << "no recorded round granted rover1's hazards first, of "
                                        << rounds_by_time.size();
}

// rover1 says it has nothing to send, and the camp grants rover2 all but rover1's least share. rover1's hazards
// start: its statuses must still leave at that share, or the camp never hears of them. In CI a status of 454
// bytes at 95 % of a 3,632 bit/s grant needed 1.05 s, was doomed against its TTL of a second every time, and
// rover1 kept that grant for the test's 30 s.
TEST_F(ChannelGrantTest, ARobotGrantedItsLeastShareStillTellsTheCampOfNewHazards) {
    ASSERT_TRUE(rover1_idle_at_its_least_share());
    publish("hazards", 1s, 41);
    EXPECT_TRUE(hazards_granted_first(20s));
}

// The camp sends rover1 commands at 10 Hz (48 bytes, 242 on the wire each: 19,360 bit/s) on the channel, and
// rover1's gateway pays for them (half duplex). They take the air whatever rover1 is granted: its grant must carry
// them on top of its least share, though rover2's bulk asks for the whole channel. Without it, in a three-robot
// run, rover1 stayed at 11,506 bit/s beside its commands, and 37 of 200 of its A were on time; here its grant
// lapsed (its statuses no longer left).
TEST_F(ChannelGrantTest, TheCampsCommandsToARobotAreInItsGrant) {
    ASSERT_TRUE(rover1_idle_at_its_least_share());
    const double least = *gateway_->granted_bps();

    fdds::DataWriterQos qos = local_->default_writer_qos();  // a camp program's defaults: reliable
    qos.lifespan().duration = passthrough::to_dds_duration(200ms);
    auto& matches = listener<MatchCounter>();
    auto* commands =
        local_->make_writer(camp_command(), fdds::TypeSupport(new idl::PaperMessagePubSubType()), qos, &matches);
    ASSERT_NE(commands, nullptr);
    ASSERT_TRUE(wait_until([&] { return matches.matched.load() > 0; })) << "the relay never read " << camp_command();
    publishers_.emplace_back([this, commands] {
        for (std::uint32_t i = 0; !stop_.load(); ++i) {
            idl::PaperMessage m;
            m.sequence_number(i);
            m.data(std::vector<std::uint8_t>(48, 1));
            commands->write(&m);
            std::this_thread::sleep_for(100ms);
        }
    });
    const auto commands_sent_bytes = [&] {
        const auto up = relay_->uplink_counts();
        return up.empty() ? std::uint64_t{0} : up.front().wire_bytes;
    };
    const bool made_room = wait_until(
        [&] {
            const auto g1 = gateway_->granted_bps();
            return g1 && *g1 > least + 15'000;
        },
        30s);
    EXPECT_TRUE(made_room) << "rover1's grant: " << gateway_->granted_bps().value_or(-1) << " bit/s, " << least
                           << " before the commands; the relay sent " << commands_sent_bytes() << " bytes of them";
    EXPECT_GT(gateway_->rate_bps(), least + 15'000) << "what rover1 budgets for";
    double total = 0;
    for (const auto& [gateway, bps] : relay_->channel_grants())
        total += bps;
    EXPECT_LE(total, CHANNEL_BPS * 1.001);
}

// A gateway the base camp has no status of (it sends none here) has no grant of its own: it budgets for the
// newcomers' share, a tenth of the channel, not for its sensor's 50 Mbit/s; and its on-robot log says so.
using NewcomerShareTest = RelayTest;

TEST_F(NewcomerShareTest, AGatewayWithoutAGrantOfItsOwnBudgetsForTheNewcomersShare) {
    GatewayConfig c = config();
    c.robot_name = "rover1";
    c.channel_grants = true;
    c.status_period = base::Duration::zero();
    c.log_file = temp_file(".db");
    start_gateway(c);
    start_relay(nullptr, 1s, {}, CHANNEL_BPS);
    const double newcomers = core::JOIN_SHARE * CHANNEL_BPS;
    const bool ok = wait_until([&] { return std::abs(gateway_->rate_bps() - newcomers) < 1; }, 20s);
    ASSERT_TRUE(ok) << "budgets for " << gateway_->rate_bps() << " bit/s";
    EXPECT_FALSE(gateway_->granted_bps()) << "no grant of its own";
    EXPECT_NEAR(relay_->newcomer_share().value_or(-1), newcomers, 1);

    // The log's link_rates: the sensor's rate, and the budget of the share the gateway goes by.
    gateway_->stop();
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open_v2(c.log_file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
    sqlite3_stmt* stmt = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT sensed_bps, budget_bps FROM link_rates ORDER BY id DESC LIMIT 1", -1,
                                 &stmt, nullptr),
              SQLITE_OK);
    ASSERT_EQ(sqlite3_step(stmt), SQLITE_ROW) << "no row in link_rates";
    EXPECT_DOUBLE_EQ(sqlite3_column_double(stmt, 0), c.scheduler.initial_rate_bps);
    EXPECT_NEAR(sqlite3_column_double(stmt, 1), newcomers * c.scheduler.budget_fraction, 1);
    sqlite3_finalize(stmt);
    sqlite3_close(db);
}

// A base-camp tool that reads the grants as a ROS 2 tool would, reliable, gets them: the grantor's writer is
// reliable (keep last, so a write never waits), and the gateways' best-effort readers match it as well.
TEST_F(NewcomerShareTest, AReliableReaderOfACampToolGetsTheGrants) {
    start_relay(nullptr, 1s, {}, CHANNEL_BPS);
    const auto tool = camp_tool();
    ASSERT_TRUE(tool->ok());
    CollectingReader<idl::ChannelGrant> grants;
    ASSERT_NE(tool->make_reader(wire::CHANNEL_GRANT_TOPIC, fdds::TypeSupport(new idl::ChannelGrantPubSubType()),
                                reliable_reader_qos(*tool), &grants),
              nullptr);
    ASSERT_TRUE(wait_until([&] { return grants.count() > 0; }, 20s)) << "no grant reached the tool";
    const idl::ChannelGrant first = grants.received().front().data;
    EXPECT_NEAR(first.rate_bps(), core::JOIN_SHARE * CHANNEL_BPS, 1) << "the newcomers' share";
}

// tm-basecamp relay --measure-channel with real participants: its WAN transport reads the send stamps that a
// standard-mode gateway's Fast DDS writes into every datagram of samples, and on loopback, where nothing queues and
// nothing is lost, the channel it shares stays at its bound.
TEST_F(RelayTest, AMeasuringRelayReadsTheSendStampsOfTheGatewaysDatagrams) {
    GatewayConfig c = config();
    c.robot_name = "rover1";
    c.channel_grants = true;
    c.status_period = 1s;  // the relay counts the datagrams of participants it heard a status from
    start_gateway(c);
    constexpr double BOUND = 30'000;
    start_relay(nullptr, 1s, {}, BOUND, true);
    const std::string topic = topic_prefix_ + "hazards";
    auto* writer = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(false));
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(relay_matched_gateway_writer(topic)) << "the relay never matched the gateway's writer";
    // The relay counts a gateway's datagrams only once it has heard that gateway's status, which under ASan beside
    // other tests came after a fixed burst of 40 samples had gone (CI, 2026-12-07): write until it has counted
    // enough, for at most 30 s.
    const auto stamped_enough = [&] {
        const auto reading = relay_->channel_reading();
        return reading && reading->queueing && reading->stamped_datagrams >= 20;
    };
    const auto deadline = std::chrono::steady_clock::now() + 30s;
    for (std::uint32_t i = 0; !stamped_enough() && std::chrono::steady_clock::now() < deadline; ++i) {
        idl::PaperMessage m;
        m.sequence_number(i);
        m.data(std::vector<std::uint8_t>(41, 1));
        ASSERT_TRUE(writer->write(&m));
        std::this_thread::sleep_for(50ms);
    }
    ASSERT_TRUE(stamped_enough()) << "the relay read no send stamps";
    const basecamp::ChannelReading reading = *relay_->channel_reading();
    EXPECT_GT(reading.datagrams, 0u);
    // Discovery leaves without its stamp (WanConfig::strip_statistics_without_samples); Fast DDS counts only the
    // datagrams it stamps, so the sequence the relay reads has no holes.
    EXPECT_LT(reading.stamped_datagrams, reading.datagrams);
    EXPECT_EQ(reading.lost_datagrams, 0u);
    EXPECT_NE(reading.verdict, core::ChannelVerdict::unknown);
    EXPECT_LT(*reading.queueing, 250ms) << "nothing queues on loopback";
    for (const auto& [gateway, bps] : relay_->channel_grants()) {
        EXPECT_LE(bps, BOUND) << "a grant above the channel's bound";
    }
}

}  // namespace
}  // namespace tgw::test
