// A large sample on a slow link, in standard WAN mode: its fragments after the first wait for the schedule
// (core::Repair::Kind::continuation), so an urgent sample goes between them, and the non-preemptive rule weighs
// the one datagram the sample holds the link for, not its whole wire time. Real participants on loopback, the
// gateway's own budget as the link.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "PaperWorkloadPubSubTypes.h"
#include "test/integration/gateway_fixture.hpp"

namespace tgw::test {
namespace {

using namespace std::chrono_literals;

std::int64_t nanoseconds_of(const eprosima::fastrtps::rtps::Time_t& t) {
    return t.to_ns();
}

TEST_F(GatewayIntegrationTest, ALargeSampleLeavesAFragmentAtATimeWithAnUrgentSampleBetween) {
    dds::GatewayConfig c = config();
    c.scheduler.initial_rate_bps = 40'000;  // 6 kB whole: 1.3 s of the budget, its first datagram 0.3 s
    start_gateway(c);
    auto& hazards = listener<CollectingReader<idl::PaperMessage>>();
    auto* hazard =
        bridge<idl::PaperMessagePubSubType>(topic_prefix_ + "hazard", robot_writer_qos(*robot_, 1s), hazards);
    auto& pictures = listener<CollectingReader<idl::PaperMessage>>();
    auto* picture =
        bridge<idl::PaperMessagePubSubType>(topic_prefix_ + "picture", robot_writer_qos(*robot_, 20s), pictures);
    ASSERT_NE(hazard, nullptr);
    ASSERT_NE(picture, nullptr);

    idl::PaperMessage msg;
    msg.data(std::vector<std::uint8_t>(40, 0x48));
    ASSERT_TRUE(hazard->write(&msg));  // the hazard topic is active: the rule protects it
    ASSERT_TRUE(wait_until([&] { return hazards.count() >= 1; }, 5s));
    std::this_thread::sleep_for(200ms);  // the link idle again

    const auto written = std::chrono::steady_clock::now();
    msg.data(std::vector<std::uint8_t>(6'000, 0x50));
    ASSERT_TRUE(picture->write(&msg));
    msg.data(std::vector<std::uint8_t>(40, 0x49));
    ASSERT_TRUE(hazard->write(&msg));
    ASSERT_TRUE(wait_until([&] { return pictures.count() >= 1 && hazards.count() >= 2; }, 10s))
        << "pictures " << pictures.count() << ", hazards " << hazards.count();
    const auto took = std::chrono::steady_clock::now() - written;

    const auto hazard_at = nanoseconds_of(hazards.received()[1].info.reception_timestamp);
    const auto picture_at = nanoseconds_of(pictures.received()[0].info.reception_timestamp);
    EXPECT_LT(hazard_at, picture_at) << "the hazard went between the picture's fragments";
    EXPECT_LT(took, 4s) << "held back whole, the picture would have waited for its deadline to come near";
    EXPECT_EQ(pictures.received()[0].data.data().size(), 6'000u);

    const auto desk = gateway_->repair_desk_counts();
    ASSERT_TRUE(desk);
    EXPECT_GE(desk->continuations_held, 3u) << "6,000 bytes are 5 fragments";
    EXPECT_GE(desk->writer_announcements_held, 2u) << "each WAN writer's announcement went in its topic's urgency";
    EXPECT_EQ(gateway_->repair_counters().writer_announcements_sent, desk->writer_announcements_held);
    const core::RepairCounters repairs = gateway_->repair_counters();
    EXPECT_EQ(repairs.continuations_sent, desk->continuations_held);
    EXPECT_EQ(repairs.continuations_late, 0u);
    expect_balanced();
}

/// The number of rows of the on-robot log `path` that `sql` counts.
std::int64_t count_rows(const std::string& path, const std::string& sql) {
    sqlite3* db = nullptr;
    std::int64_t n = -1;
    if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
        sqlite3_stmt* stmt = nullptr;
        if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr) == SQLITE_OK && sqlite3_step(stmt) == SQLITE_ROW) {
            n = sqlite3_column_int64(stmt, 0);
        }
        sqlite3_finalize(stmt);
    }
    sqlite3_close(db);
    return n;
}

TEST_F(GatewayIntegrationTest, ALargeSampleWhoseFragmentsCannotAllLeaveInTimeIsLoggedNotCountedForwarded) {
    dds::GatewayConfig c = config();
    c.log_file = temp_file(".db");
    c.scheduler.initial_rate_bps = 40'000;
    start_gateway(c);
    auto& pictures = listener<CollectingReader<idl::PaperMessage>>();
    auto* picture =
        bridge<idl::PaperMessagePubSubType>(topic_prefix_ + "picture", robot_writer_qos(*robot_, 3s), pictures);
    ASSERT_NE(picture, nullptr);

    idl::PaperMessage msg;
    msg.data(std::vector<std::uint8_t>(6'000, 0x50));
    ASSERT_TRUE(picture->write(&msg));
    // Its first datagram leaves at once; then the link falls to where a fragment is 5 s of it.
    ASSERT_TRUE(wait_until([&] { return gateway_->repair_desk_counts()->continuations_held > 0; }, 5s));
    gateway_->set_rate(2'000);
    ASSERT_TRUE(wait_until([&] { return gateway_->repair_counters().samples_cut_short >= 1; }, 5s));
    std::this_thread::sleep_for(500ms);
    EXPECT_EQ(pictures.count(), 0u);

    const core::TopicId id = gateway_->find_topic(topic_prefix_ + "picture")->id;
    const core::TopicCounters counters = gateway_->counters(id);
    EXPECT_EQ(counters.forwarded, 0u);
    EXPECT_EQ(counters.dropped_for(core::DropReason::doomed), 1u);
    expect_balanced();
    EXPECT_EQ(gateway_->repair_counters().continuations_sent, 0u);

    gateway_->stop();
    EXPECT_EQ(count_rows(c.log_file,
                         "SELECT COUNT(*) FROM dropped_samples WHERE reason = 'doomed' AND "
                         "length(payload) > 6000"),
              1)
        << "kept whole, with its reason";
    EXPECT_EQ(count_rows(c.log_file, "SELECT COUNT(*) FROM forwarded_samples"), 0)
        << "it never left whole: the mission archive must not count it lost on the link";
}

}  // namespace
}  // namespace tgw::test
