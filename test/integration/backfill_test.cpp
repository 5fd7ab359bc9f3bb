// Backfill with real participants in one process: robot writer -> Gateway (its on-robot log) -> Relay with a
// recording. What the log kept reaches the camp's recording, never its live domain; the camp's acknowledgements
// mark the log's rows; a hazard written meanwhile keeps its deadline.
#include <gtest/gtest.h>

#include <sqlite3.h>

#include <string>

#include "PaperWorkloadPubSubTypes.h"
#include "basecamp/capture/backfill_archive.hpp"
#include "basecamp/recording/sample_store.hpp"
#include "test/integration/relay_fixture.hpp"

namespace tgw::test {
namespace {

/// One integer a query on the SQLite file at `path` gives; -1 when it gives none.
std::int64_t query(const std::string& path, const std::string& sql) {
    sqlite3* db = nullptr;
    std::int64_t value = -1;
    if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
        sqlite3_stmt* stmt = nullptr;
        if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr) == SQLITE_OK && sqlite3_step(stmt) == SQLITE_ROW)
            value = sqlite3_column_int64(stmt, 0);
        sqlite3_finalize(stmt);
    }
    sqlite3_close_v2(db);
    return value;
}

class BackfillTest : public RelayTest {
  protected:
    /// A gateway with backfill and its log, at `rate_bps`, and a relay recording into its store with an archive.
    void start(double rate_bps, bool compact = false, bool backfill = true) {
        GatewayConfig c = config();
        c.compact_wan = compact;
        log_path_ = temp_file("-robot.db");
        c.log_file = log_path_;
        c.backfill = backfill;
        c.scheduler.initial_rate_bps = rate_bps;
        start_gateway(c);
        camp_path_ = temp_file("-camp.db");
        store_ = std::make_unique<basecamp::SampleStore>(camp_path_, "--out", 50);
        archive_ = std::make_unique<basecamp::BackfillArchive>(*store_);
        start_relay(store_.get(), 1s, {}, 0, false, archive_.get());
    }

    void TearDown() override {
        stop_camp();
        RelayTest::TearDown();
    }

    /// Stops the relay and closes its recording, as a camp laptop that goes down.
    void stop_camp() {
        stop_relay_.store(true);
        if (relay_thread_.joinable())
            relay_thread_.join();
        relay_.reset();
        archive_.reset();
        store_.reset();
    }

    /// A relay started anew on the same recording.
    void restart_camp() {
        stop_camp();
        stop_relay_.store(false);
        store_ = std::make_unique<basecamp::SampleStore>(camp_path_, "--out", 50);
        archive_ = std::make_unique<basecamp::BackfillArchive>(*store_);
        start_relay(store_.get(), 1s, {}, 0, false, archive_.get());
    }

    /// Writes `n` samples of `bytes` on `writer`, `gap` apart.
    static void write(fdds::DataWriter* writer, int n, std::size_t bytes, base::Duration gap = base::Duration::zero()) {
        for (int i = 0; i < n; ++i) {
            idl::PaperMessage m;
            m.generated_ns(static_cast<std::uint64_t>(i));
            m.data(std::vector<std::uint8_t>(bytes, static_cast<std::uint8_t>(i)));
            ASSERT_EQ(writer->write_w_timestamp(&m, fdds::HANDLE_NIL, stamp_now()), ReturnCode_t::RETCODE_OK);
            std::this_thread::sleep_for(gap);
        }
    }

    core::TopicCounters counts(const std::string& topic) const {
        const auto bridged = gateway_->find_topic(topic);
        return bridged ? gateway_->counters(bridged->id) : core::TopicCounters{};
    }

    std::int64_t camp(const std::string& sql) {
        store_->flush();
        return query(camp_path_, sql);
    }

    std::string log_path_;
    std::string camp_path_;
    std::unique_ptr<basecamp::SampleStore> store_;
    std::unique_ptr<basecamp::BackfillArchive> archive_;

    /// `n` samples of 1,000 bytes (TTL 0.3 s) expire into the log while the link is down; the link comes back at
    /// 20,000 bit/s, where they take about 0.5 s each, and returns once the camp has acknowledged 3.
    void begin_backfill_of(const std::string& topic, int n) {
        auto* writer =
            robot_writer<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_, std::chrono::milliseconds(300)));
        ASSERT_NE(writer, nullptr);
        ASSERT_TRUE(relay_matched_gateway_writer(topic));
        gateway_->set_wan_link_up(false);
        write(writer, n, 1000);
        ASSERT_TRUE(wait_until(
            [&] { return counts(topic).dropped_for(core::DropReason::expired) >= static_cast<std::uint64_t>(n); }));
        gateway_->set_rate(20'000);
        gateway_->set_wan_link_up(true);
        ASSERT_TRUE(wait_until([&] { return archive_->acknowledged() >= 3; }, 20s)) << "backfill has begun";
    }

    /// Samples expire while the link is down and go to the log; once it is up, they reach the camp's recording,
    /// and not its live domain, and the log marks them acknowledged.
    void expect_what_the_log_kept_in_the_archive();
};

TEST_F(BackfillTest, WhatTheLogKeptReachesTheCampsRecordingNotItsDomainAndIsAcknowledged) {
    start(50e6);
    expect_what_the_log_kept_in_the_archive();
}

TEST_F(BackfillTest, InCompactModeTheLogsRowsRideInBundlesToTheArchive) {
    start(50e6, true);
    expect_what_the_log_kept_in_the_archive();
}

void BackfillTest::expect_what_the_log_kept_in_the_archive() {
    const std::string topic = topic_prefix_ + "expiring";
    auto& local = listener<CollectingReader<idl::PaperMessage>>();
    local_reader<idl::PaperMessagePubSubType>(topic, local_->default_reader_qos(), local);
    auto* writer = robot_writer<idl::PaperMessagePubSubType>(
        topic, robot_writer_qos(*robot_, std::chrono::milliseconds(300)));  // a TTL of 0.3 s
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(relay_matched_gateway_writer(topic));

    // The radio goes: the samples wait, expire and go to the log.
    gateway_->set_wan_link_up(false);
    constexpr int N = 20;
    write(writer, N, 200);
    ASSERT_TRUE(wait_until([&] { return counts(topic).dropped_for(core::DropReason::expired) >= N; }))
        << "expired: " << counts(topic).dropped_for(core::DropReason::expired);
    gateway_->set_wan_link_up(true);

    ASSERT_TRUE(wait_until([&] { return archive_->acknowledged() >= static_cast<std::uint64_t>(N); }, 20s))
        << "acknowledged " << archive_->acknowledged() << " of " << N;
    EXPECT_EQ(camp("SELECT COUNT(*) FROM samples WHERE backfilled = 1 AND topic = '" + topic + "'"), N);
    EXPECT_EQ(camp("SELECT COUNT(DISTINCT row_id) FROM samples WHERE backfilled = 1"), N);
    // Its TTL as the robot applied it: from the source time to the deadline (set on the robot's steady clock).
    EXPECT_EQ(camp("SELECT COUNT(*) FROM samples WHERE backfilled = 1 AND drop_reason = 'expired' AND "
                   "lifespan_ns BETWEEN 299000000 AND 301000000 AND length(payload) > 200 AND source_ns > 0"),
              N)
        << "each with its TTL, why it stayed, its source time and payload";
    EXPECT_EQ(camp("SELECT COUNT(*) FROM samples WHERE topic = 'tgw/backfill'"), 0) << "stored as its own topic";
    ASSERT_TRUE(wait_until(
        [&] { return query(log_path_, "SELECT COUNT(*) FROM dropped_samples WHERE acked_ns IS NOT NULL") == N; }, 10s))
        << "the robot's log marks what the camp stored";
    EXPECT_EQ(local.count(), 0u) << "past its TTL: never on the camp's live domain";
    EXPECT_EQ(relay_->relayed().count("tgw/backfill"), 0u);
    EXPECT_EQ(relay_->relayed()[topic], 0u);
}

TEST_F(BackfillTest, WithBackfillOffTheLogKeepsItsRowsAndSendsTheCampNone) {
    // --no-backfill: the same rows expire into the log, and the link idles at 50 Mbit/s for 3 s after.
    start(50e6, false, false);
    const std::string topic = topic_prefix_ + "expiring";
    auto* writer =
        robot_writer<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_, std::chrono::milliseconds(300)));
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(relay_matched_gateway_writer(topic));
    gateway_->set_wan_link_up(false);
    constexpr int N = 20;
    write(writer, N, 200);
    ASSERT_TRUE(wait_until([&] { return counts(topic).dropped_for(core::DropReason::expired) >= N; }));
    gateway_->set_wan_link_up(true);
    std::this_thread::sleep_for(3s);

    EXPECT_FALSE(gateway_->backfill_summary().has_value()) << "no backfill sender";
    EXPECT_EQ(archive_->received(), 0u);
    EXPECT_EQ(camp("SELECT COUNT(*) FROM samples WHERE backfilled = 1"), 0);
    EXPECT_EQ(query(log_path_, "SELECT COUNT(*) FROM dropped_samples WHERE acked_ns IS NULL AND sends = 0"), N)
        << "every row still on the robot, none sent";
}

TEST_F(BackfillTest, AGatewayRestartedMidBackfillGoesOnWhereItStoppedAndTheCampStoresEachRowOnce) {
    // 20,000 bit/s: 40 rows of 1,000 bytes take about 20 s; the gateway is stopped after a few, and made anew on
    // the same log.
    start(50e6);
    constexpr int N = 40;
    begin_backfill_of(topic_prefix_ + "pictures", N);
    if (HasFatalFailure())
        return;

    GatewayConfig c = config();
    c.log_file = log_path_;
    c.backfill = true;
    c.scheduler.initial_rate_bps = 200'000;
    gateway_.reset();
    const std::uint64_t before = archive_->received();
    ASSERT_LT(before, static_cast<std::uint64_t>(N)) << "stopped mid-backfill";
    start_gateway(c);

    ASSERT_TRUE(wait_until(
        [&] { return query(log_path_, "SELECT COUNT(*) FROM dropped_samples WHERE acked_ns IS NOT NULL") == N; }, 30s))
        << "acknowledged in the log: "
        << query(log_path_, "SELECT COUNT(*) FROM dropped_samples WHERE acked_ns IS NOT NULL") << " of " << N;
    EXPECT_EQ(camp("SELECT COUNT(*) FROM samples WHERE backfilled = 1"), N) << "each row stored once";
    EXPECT_EQ(camp("SELECT COUNT(DISTINCT log_id) FROM samples WHERE backfilled = 1"), 1) << "one log, both runs";
    // A row the first gateway sent whose acknowledgement it did not hear may cross again; it is stored once.
    EXPECT_LE(store_->duplicate_backfill_rows(), 4u);
}

TEST_F(BackfillTest, ACampRestartedMidBackfillOnTheSameRecordingGetsTheRestAndStoresEachRowOnce) {
    // 20,000 bit/s: 40 rows of 1,000 bytes take about 20 s; the camp's relay goes after a few, and comes back on
    // the same recording.
    start(50e6);
    constexpr int N = 40;
    begin_backfill_of(topic_prefix_ + "pictures", N);
    if (HasFatalFailure())
        return;

    stop_camp();
    const std::int64_t stored_before = query(camp_path_, "SELECT COUNT(*) FROM samples WHERE backfilled = 1");
    ASSERT_GE(stored_before, 3);
    ASSERT_LT(stored_before, N) << "stopped mid-backfill";
    gateway_->set_rate(200'000);
    restart_camp();

    ASSERT_TRUE(wait_until(
        [&] { return query(log_path_, "SELECT COUNT(*) FROM dropped_samples WHERE acked_ns IS NOT NULL") == N; }, 30s))
        << "acknowledged in the log: "
        << query(log_path_, "SELECT COUNT(*) FROM dropped_samples WHERE acked_ns IS NOT NULL") << " of " << N;
    EXPECT_EQ(camp("SELECT COUNT(*) FROM samples WHERE backfilled = 1"), N) << "each row stored once";
    EXPECT_EQ(camp("SELECT COUNT(DISTINCT row_id) FROM samples WHERE backfilled = 1"), N);
}

TEST_F(BackfillTest, AHazardWrittenWhileBackfillFillsTheLinkKeepsItsDeadline) {
    // 20,000 bit/s: a backfilled row of 1,000 bytes holds the link about 0.5 s; a hazard (TTL 1 s, 0.1 s of wire)
    // every 250 ms.
    start(50e6);
    const std::string rows = topic_prefix_ + "pictures";
    const std::string hazard = topic_prefix_ + "hazard";
    auto* pictures =
        robot_writer<idl::PaperMessagePubSubType>(rows, robot_writer_qos(*robot_, std::chrono::milliseconds(300)));
    auto& hazards = listener<CollectingReader<idl::PaperMessage>>();
    local_reader<idl::PaperMessagePubSubType>(hazard, local_->default_reader_qos(), hazards);
    auto* hazard_writer = robot_writer<idl::PaperMessagePubSubType>(hazard, robot_writer_qos(*robot_, 1s));
    ASSERT_TRUE(pictures != nullptr && hazard_writer != nullptr);
    ASSERT_TRUE(relay_matched_gateway_writer(rows) && relay_matched_gateway_writer(hazard));
    ASSERT_TRUE(wait_until([&] { return relay_->local_readers(hazard) > 0; }));

    gateway_->set_wan_link_up(false);
    constexpr int ROWS = 30;
    write(pictures, ROWS, 1000);
    ASSERT_TRUE(wait_until([&] { return counts(rows).dropped_for(core::DropReason::expired) >= ROWS; }));
    gateway_->set_rate(20'000);
    gateway_->set_wan_link_up(true);
    ASSERT_TRUE(wait_until([&] { return archive_->received() >= 2; }, 10s)) << "backfill has begun";

    constexpr int HAZARDS = 20;
    write(hazard_writer, HAZARDS, 41, std::chrono::milliseconds(250));
    ASSERT_TRUE(wait_until([&] { return hazards.count() >= HAZARDS; }, 10s)) << "hazards " << hazards.count();
    base::Duration worst{};
    for (const auto& received : hazards.received()) {
        const auto& stamp = received.info.source_timestamp;
        const auto& arrived = received.info.reception_timestamp;
        const base::Duration late = std::chrono::seconds(arrived.seconds() - stamp.seconds()) +
                                    std::chrono::nanoseconds(static_cast<std::int64_t>(arrived.nanosec()) -
                                                             static_cast<std::int64_t>(stamp.nanosec()));
        worst = std::max(worst, late);
    }
    EXPECT_LE(worst, 1s) << "the latest hazard took " << base::to_seconds(worst) << " s";
    EXPECT_EQ(counts(hazard).forwarded, static_cast<std::uint64_t>(HAZARDS));
    EXPECT_GE(archive_->received(), 5u) << "backfill went on between the hazards";
}

}  // namespace
}  // namespace tgw::test
