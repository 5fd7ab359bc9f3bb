// tm-basecamp merge on real participants in one process: robot writers -> Gateway with an on-robot log and a link
// too slow for what they publish -> tm-basecamp record's Recorder writing a real recording; then the two files
// merged into the mission archive, twice.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <memory>
#include <string>
#include <thread>

#include "KeyedReadingPubSubTypes.h"
#include "PaperWorkloadPubSubTypes.h"
#include "base/peer_transport.hpp"
#include "basecamp/analysis/mission_archive.hpp"
#include "basecamp/capture/recorder.hpp"
#include "basecamp/recording/sample_store.hpp"
#include "test/integration/gateway_fixture.hpp"

namespace tgw::test {
namespace {

/// The one number `sql` gives on `path`, with `attached` (when given) as schema `other`.
std::int64_t number(const std::string& path, const std::string& sql, const std::string& attached = "") {
    sqlite3* db = nullptr;
    std::int64_t value = -1;
    if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK &&
        (attached.empty() || sqlite3_exec(db, ("ATTACH DATABASE '" + attached + "' AS other").c_str(), nullptr, nullptr,
                                          nullptr) == SQLITE_OK)) {
        sqlite3_stmt* stmt = nullptr;
        if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr) == SQLITE_OK && sqlite3_step(stmt) == SQLITE_ROW)
            value = sqlite3_column_int64(stmt, 0);
        else
            ADD_FAILURE() << path << ": " << sqlite3_errmsg(db) << " in " << sql;
        sqlite3_finalize(stmt);
    }
    sqlite3_close(db);
    return value;
}

class MissionArchiveTest : public GatewayIntegrationTest {
  protected:
    void SetUp() override {
        GatewayIntegrationTest::SetUp();
        basecamp_.reset();  // the recorder is the base camp
    }

    void TearDown() override {
        stop_recorder();
        GatewayIntegrationTest::TearDown();
    }

    /// tm-basecamp record at the base camp: unicast to the robot on loopback, no receiver reports.
    void start_recorder(const std::string& path) {
        store_ = std::make_unique<basecamp::SampleStore>(path, "--out", 50);
        base::PeerTransport transport;
        transport.peers = {"127.0.0.1"};
        transport.interface = "127.0.0.1";
        recorder_ = std::make_unique<basecamp::Recorder>(domains_.wan, transport, *store_, base::Duration::zero());
        recorder_thread_ = std::thread([this] { recorder_->run(std::chrono::minutes(5), stop_); });
    }

    /// Stops the recorder and commits all it recorded.
    void stop_recorder() {
        stop_.store(true);
        if (recorder_thread_.joinable())
            recorder_thread_.join();
        recorder_.reset();
        store_.reset();
    }

    /// A reliable robot writer of `topic` whose samples live 2 s, once the gateway bridges it both ways.
    template <typename PubSubType>
    fdds::DataWriter* robot_writer(const std::string& topic) {
        auto& matches = listener<MatchCounter>();
        auto* writer = robot_->make_writer(topic, fdds::TypeSupport(new PubSubType()),
                                           robot_writer_qos(*robot_, std::chrono::seconds(2)), &matches);
        if (writer == nullptr || !gateway_->wait_for_topic(topic, MATCH_TIMEOUT))
            return nullptr;
        const core::TopicId id = gateway_->find_topic(topic)->id;
        const bool matched = wait_until(
            [&] {
                return matches.matched.load() > 0 && gateway_->robot_matched_writers(id) > 0 &&
                       gateway_->wan_matched_readers(id) > 0;
            },
            MATCH_TIMEOUT);
        return matched ? writer : nullptr;
    }

    std::unique_ptr<basecamp::SampleStore> store_;
    std::unique_ptr<basecamp::Recorder> recorder_;
    std::thread recorder_thread_;
    std::atomic<bool> stop_{false};
};

TEST_F(MissionArchiveTest, HoldsEveryPublishedSampleOnceWhilePartOfThemWentToTheOnRobotLog) {
    GatewayConfig c = config();
    c.log_file = temp_file("-robot.db");
    // The recorder's participant takes one of the first ports of the WAN domain on loopback.
    c.wan_peers = {"127.0.0.1"};
    c.wan_peer_participants = 16;
    start_gateway(c);
    const std::string recording = temp_file("-basecamp.db");
    start_recorder(recording);
    const std::string paper = topic_prefix_ + "paper";
    const std::string keyed = topic_prefix_ + "keyed";
    auto* paper_writer = robot_writer<idl::PaperMessagePubSubType>(paper);
    auto* keyed_writer = robot_writer<idl::KeyedReadingPubSubType>(keyed);
    ASSERT_TRUE(paper_writer != nullptr && keyed_writer != nullptr) << "the gateway never bridged both topics";
    // Discovery was charged at the fast rate; now a link that carries a small part of what follows in 2 s.
    gateway_->set_rate(20000);

    constexpr std::uint64_t PAPER = 100;
    constexpr std::uint64_t KEYED = 40;
    for (std::uint64_t i = 0; i < PAPER; ++i) {
        idl::PaperMessage m;
        m.generated_ns(i);
        m.data(std::vector<std::uint8_t>(266, static_cast<std::uint8_t>(i)));
        ASSERT_TRUE(paper_writer->write(&m));
    }
    for (std::uint32_t i = 0; i < KEYED; ++i) {
        idl::KeyedReading r;
        r.sensor_id(i % 4);
        r.value(i);
        ASSERT_TRUE(keyed_writer->write(&r));
    }
    const core::TopicId paper_id = gateway_->find_topic(paper)->id;
    const core::TopicId keyed_id = gateway_->find_topic(keyed)->id;
    ASSERT_TRUE(wait_until([&] {
        return gateway_->counters(paper_id).received >= PAPER && gateway_->counters(keyed_id).received >= KEYED;
    }));
    ASSERT_TRUE(wait_until([&] { return gateway_->queued_samples() == 0; }, 10s));
    gateway_->stop();  // the on-robot log is flushed
    const core::TopicCounters p = gateway_->counters(paper_id);
    const core::TopicCounters k = gateway_->counters(keyed_id);
    const std::uint64_t forwarded = p.forwarded + k.forwarded;
    const std::string both = "topic IN ('" + paper + "', '" + keyed + "')";
    // What left the robot arrives within moments on loopback; what has not by then counts as lost.
    wait_until(
        [&] {
            store_->flush();
            return number(recording, "SELECT COUNT(*) FROM samples WHERE " + both) >=
                   static_cast<std::int64_t>(forwarded);
        },
        5s);
    stop_recorder();
    const std::int64_t recorded = number(recording, "SELECT COUNT(*) FROM samples WHERE " + both);

    const std::string archive = temp_file("-mission.db");
    const std::string again = temp_file("-again.db");
    const auto first = basecamp::merge_mission(c.log_file, recording, archive);
    const auto second = basecamp::merge_mission(c.log_file, recording, again);
    ASSERT_TRUE(first && second);

    EXPECT_EQ(number(archive, "SELECT COUNT(*) FROM mission_samples"), static_cast<std::int64_t>(PAPER + KEYED));
    EXPECT_EQ(first->total.produced(), PAPER + KEYED);
    ASSERT_EQ(first->topics.size(), 2u);
    for (const basecamp::TopicFates& t : first->topics)
        EXPECT_EQ(t.produced(), t.topic == paper ? PAPER : KEYED) << t.topic;
    EXPECT_GT(first->total.dropped_total(), 0u) << "part of the samples must have gone to the log";
    EXPECT_GT(first->total.received, 0u);
    EXPECT_EQ(static_cast<std::int64_t>(first->total.dropped_total()),
              number(c.log_file, "SELECT COUNT(*) FROM dropped_samples"));
    EXPECT_EQ(first->total.dropped_total(), p.dropped_total() + k.dropped_total());
    EXPECT_EQ(first->total.received + first->total.lost, forwarded);
    EXPECT_EQ(static_cast<std::int64_t>(first->total.received), recorded);
    EXPECT_EQ(first->total.received_unmatched, 0u) << "every recorded sample is one the gateway forwarded";
    // The writers are transient local (Fast DDS's default): their lanes' latched history takes each payload
    // written instead of copying it; the log still gives each forwarded sample its size.
    EXPECT_EQ(number(c.log_file, "SELECT COUNT(*) FROM forwarded_samples WHERE topic = '" + paper +
                                     "' AND payload_bytes > 266 AND payload_bytes < 300"),
              static_cast<std::int64_t>(p.forwarded));
    EXPECT_EQ(number(archive, "SELECT COUNT(DISTINCT instance_key) FROM mission_samples WHERE topic = '" + keyed + "'"),
              4);

    EXPECT_EQ(number(archive, "SELECT COUNT(*) FROM mission_samples"),
              number(again, "SELECT COUNT(*) FROM mission_samples"));
    EXPECT_EQ(number(archive,
                     "SELECT (SELECT COUNT(*) FROM (SELECT * FROM main.mission_samples EXCEPT "
                     "SELECT * FROM other.mission_samples)) + (SELECT COUNT(*) FROM (SELECT * FROM main.meta EXCEPT "
                     "SELECT * FROM other.meta))",
                     again),
              0)
        << "a second merge of the same files gave other rows";
}

}  // namespace
}  // namespace tgw::test
