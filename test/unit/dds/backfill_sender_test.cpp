// BackfillSender against a real on-robot log (an SQLite file in a temporary directory); no DDS.
#include "gateway/dds/backfill_sender.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include "test/fakes/fake_clock.hpp"
#include "wire/backfill_codec.hpp"

namespace tgw::dds {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

class BackfillSenderTest : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("tgw-backfill-sender-" + std::to_string(::getpid()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
        log_ = std::make_unique<log::RobotLog>((dir_ / "robot-log.db").string());
    }
    void TearDown() override {
        sender_.reset();
        log_.reset();
        fs::remove_all(dir_);
    }

    /// A sample of `topic` with a TTL of `ttl`, born `age` ago, logged as expired.
    void log_dropped(const std::string& topic, base::Duration ttl, base::Duration age, std::size_t bytes = 100) {
        core::Sample sample;
        sample.payload.assign(bytes, 0x5A);
        sample.source_time = clock_.wall_now() - std::chrono::duration_cast<base::WallClock::duration>(age);
        log::LogRecord record;
        record.topic = topic;
        record.type_name = "T";
        record.sample = &sample;
        record.reason = core::DropReason::expired;
        record.arrival = sample.source_time;
        record.deadline = sample.source_time + std::chrono::duration_cast<base::WallClock::duration>(ttl);
        record.logged_at = clock_.wall_now();
        log_->append(record);
    }

    void start(BackfillSender::Config config = {}) {
        config.poll = 10ms;
        sender_ = std::make_unique<BackfillSender>(*log_, config, core::WireModel{}, clock_, [this] { ++wakes_; });
        sender_->start(7);
    }

    /// Waits up to 5 s for the sender to have a sample ready, and takes it.
    std::optional<core::Sample> next() {
        for (int i = 0; i < 500; ++i) {
            if (std::optional<core::Sample> sample = sender_->next_when_idle(clock_.now()))
                return sample;
            std::this_thread::sleep_for(10ms);
        }
        return std::nullopt;
    }

    /// The topic a sample handed out carries.
    static std::string topic_of(const core::Sample& sample) { return wire::decode_backfill(sample.payload)->topic(); }

    std::int64_t column(const std::string& sql) {
        sqlite3* db = nullptr;
        sqlite3_open_v2((dir_ / "robot-log.db").c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
        sqlite3_stmt* stmt = nullptr;
        sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr);
        const std::int64_t value = sqlite3_step(stmt) == SQLITE_ROW ? sqlite3_column_int64(stmt, 0) : -1;
        sqlite3_finalize(stmt);
        sqlite3_close_v2(db);
        return value;
    }

    fs::path dir_;
    test::FakeClock clock_;
    std::unique_ptr<log::RobotLog> log_;
    std::unique_ptr<BackfillSender> sender_;
    std::atomic<int> wakes_{0};
};

TEST_F(BackfillSenderTest, HandsOutTheLogsRowsShortestTtlFirstAsSamplesOfItsTopic) {
    log_dropped("D", 20s, 30s);
    log_dropped("C", 5s, 20s);
    log_dropped("B", 2s, 10s);
    log_->flush();
    start();
    std::vector<std::string> order;
    for (int i = 0; i < 3; ++i) {
        const std::optional<core::Sample> sample = next();
        ASSERT_TRUE(sample) << "sample " << i;
        EXPECT_EQ(sample->topic, 7u);
        order.push_back(topic_of(*sample));
    }
    EXPECT_EQ(order, (std::vector<std::string>{"B", "C", "D"}));
    EXPECT_EQ(sender_->backlog().rows, 3u) << "none acknowledged yet";
}

TEST_F(BackfillSenderTest, ASampleThatLeftIsCountedInTheLogAndAnAcknowledgementMarksItsRow) {
    log_dropped("B", 2s, 10s);
    log_dropped("C", 5s, 10s);
    log_->flush();
    start();
    const std::optional<core::Sample> first = next();
    ASSERT_TRUE(first);
    const std::int64_t row = *wire::backfill_row_id(first->payload);
    sender_->left(row, first->payload.size());
    std::array<std::uint8_t, 16> someone_else = sender_->log_id();
    someone_else[0] ^= 0xFF;
    sender_->acknowledged(someone_else, {{row, row}});
    EXPECT_EQ(sender_->backlog().rows, 2u) << "another log's acknowledgement";
    sender_->acknowledged(sender_->log_id(), {{row, row}});
    EXPECT_EQ(sender_->backlog().rows, 1u);
    EXPECT_EQ(sender_->counts().acknowledged, 1u);
    log_->flush();
    EXPECT_EQ(column("SELECT sends FROM dropped_samples WHERE id = " + std::to_string(row)), 1);
    EXPECT_EQ(column("SELECT acked_ns IS NOT NULL FROM dropped_samples WHERE id = " + std::to_string(row)), 1);
    EXPECT_EQ(column("SELECT COUNT(*) FROM dropped_samples WHERE acked_ns IS NULL"), 1);
}

TEST_F(BackfillSenderTest, ARowThatDidNotLeaveGoesAgainAndOneThatLeftWaitsForItsAcknowledgement) {
    BackfillSender::Config config;
    config.planner.resend_after = 1h;  // the fake clock never gets there
    log_dropped("B", 2s, 10s);
    log_->flush();
    start(config);
    std::optional<core::Sample> sample = next();
    ASSERT_TRUE(sample);
    const std::int64_t row = *wire::backfill_row_id(sample->payload);
    sender_->not_left(row);
    sample = next();
    ASSERT_TRUE(sample) << "handed out again";
    EXPECT_EQ(wire::backfill_row_id(sample->payload), row);
    sender_->left(row, sample->payload.size());
    std::this_thread::sleep_for(100ms);
    EXPECT_FALSE(sender_->next_when_idle(clock_.now())) << "waits for its acknowledgement";
}

TEST_F(BackfillSenderTest, RowsLoggedAfterTheStartAreFoundAndTheLoopIsWokenForThem) {
    start();
    EXPECT_FALSE(sender_->next_when_idle(clock_.now())) << "nothing logged yet";
    log_dropped("A", 1s, 2s);
    log_->flush();
    for (int i = 0; i < 500 && wakes_.load() == 0; ++i)
        std::this_thread::sleep_for(10ms);
    EXPECT_GE(wakes_.load(), 1) << "the loop was told none, then woken";
    EXPECT_TRUE(sender_->next_ready(clock_.now()));
    const std::optional<core::Sample> sample = next();
    ASSERT_TRUE(sample);
    EXPECT_EQ(topic_of(*sample), "A");
}

}  // namespace
}  // namespace tgw::dds
