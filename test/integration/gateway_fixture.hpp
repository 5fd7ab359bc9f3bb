#pragma once

// The fixture of the gateway's integration tests: a robot participant, a base-camp participant and the Gateway
// between them, in one process, on domains of this process.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/clock.hpp"
#include "gateway/dds/gateway.hpp"
#include "passthrough/dds_time.hpp"
#include "test/integration/dds_test_support.hpp"
#include "test/integration/error_log_counter.hpp"

namespace tgw::test {

using namespace std::chrono_literals;
using dds::Gateway;
using dds::GatewayConfig;

inline constexpr auto MATCH_TIMEOUT = std::chrono::milliseconds(8000);

class GatewayIntegrationTest : public ::testing::Test {
  protected:
    void SetUp() override {
        ErrorLogCounter::instance().take_errors();
        use_transports_in_process();
        domains_ = TestDomains::for_this_process();
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        topic_prefix_ = std::string("tgw_it/") + info->name() + "/";
        robot_ = std::make_unique<TestParticipant>(domains_.robot, TestParticipant::robot_qos());
        ASSERT_TRUE(robot_->ok());
        basecamp_ = std::make_unique<TestParticipant>(
            domains_.wan, TestParticipant::wan_qos(domains_.wan_reader_port, domains_.gateway_wan_port), &watcher_);
        ASSERT_TRUE(basecamp_->ok());
    }

    void TearDown() override {
        gateway_.reset();
        robot_.reset();
        basecamp_.reset();
        listeners_.clear();
        for (const std::string& file : files_) {
            std::remove(file.c_str());
            std::remove((file + "-wal").c_str());
            std::remove((file + "-shm").c_str());
        }
        const auto errors = ErrorLogCounter::instance().take_errors();
        std::string all;
        for (const auto& e : errors) {
            all += e + "\n";
        }
        EXPECT_TRUE(errors.empty()) << "Fast DDS logged errors:\n" << all;
    }

    GatewayConfig config() const {
        GatewayConfig c;
        c.robot_domain = domains_.robot;
        c.wan_domain = domains_.wan;
        c.wan_peers = {"127.0.0.1:" + std::to_string(domains_.wan_reader_port)};
        c.wan_interface = "127.0.0.1";
        c.wan_port = domains_.gateway_wan_port;
        c.scheduler.initial_rate_bps = 50e6;
        c.default_ttl = 5s;
        return c;
    }

    void start_gateway(const GatewayConfig& c) { gateway_ = std::make_unique<Gateway>(c, clock_); }

    /// A listener that outlives the entities it is attached to (they are deleted in TearDown).
    template <typename T>
    T& listener() {
        auto owned = std::make_shared<T>();
        listeners_.push_back(owned);
        return *owned;
    }

    std::string temp_file(const std::string& suffix) {
        const std::string path = "/tmp/tgw_it_" + std::to_string(::getpid()) + "_" +
                                 ::testing::UnitTest::GetInstance()->current_test_info()->name() + suffix;
        files_.push_back(path);
        std::remove(path.c_str());
        return path;
    }

    /// A --qos file with one best-effort data_writer profile for `topic`: Lifespan `lifespan_s`, then `extra`.
    std::string writer_profile_file(const std::string& topic, int lifespan_s, const std::string& extra) {
        const std::string xml = temp_file(".xml");
        std::ofstream out(xml);
        out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
               "<dds xmlns=\"http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles\"><profiles>\n"
               "<data_writer profile_name=\""
            << topic << "\"><qos><reliability><kind>BEST_EFFORT</kind></reliability><lifespan><duration><sec>"
            << lifespan_s << "</sec><nanosec>0</nanosec></duration></lifespan></qos>" << extra
            << "</data_writer>\n</profiles></dds>\n";
        return xml;
    }

    static fdds::DataWriterQos robot_writer_qos(TestParticipant& p, std::optional<base::Duration> lifespan = {}) {
        fdds::DataWriterQos q = p.default_writer_qos();
        q.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
        q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        q.history().depth = 1000;
        if (lifespan) {
            q.lifespan().duration = passthrough::to_dds_duration(*lifespan);
        }
        return q;
    }

    static fdds::DataReaderQos wan_reader_qos(TestParticipant& p) {
        fdds::DataReaderQos q = p.default_reader_qos();
        q.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
        q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        q.history().depth = 1000;
        return q;
    }

    /// Waits until the gateway bridges `topic`, its robot reader matched `writer_matches` and its WAN writer
    /// matched `reader_matches`, each for up to `timeout`.
    void wait_for_bridge(const std::string& topic, const MatchCounter& writer_matches,
                         const std::atomic<int>& reader_matches, std::chrono::milliseconds timeout = MATCH_TIMEOUT) {
        ASSERT_TRUE(gateway_->wait_for_topic(topic, timeout)) << topic << " was never bridged";
        ASSERT_TRUE(wait_until([&] { return writer_matches.matched.load() > 0; }, timeout))
            << "the gateway's robot reader never matched " << topic;
        ASSERT_TRUE(wait_until([&] { return reader_matches.load() > 0; }, timeout))
            << "the base camp never matched the gateway's WAN writer of " << topic;
        // Both ends must know each other: the WAN writer is best effort, so what it writes before it has
        // matched the base camp's reader is lost for good.
        const core::TopicId id = gateway_->find_topic(topic)->id;
        ASSERT_TRUE(wait_until([&] { return gateway_->wan_matched_readers(id) > 0; }, timeout))
            << "the gateway's WAN writer never matched the base camp's reader of " << topic;
        ASSERT_TRUE(wait_until([&] { return gateway_->robot_matched_writers(id) > 0; }, timeout))
            << "the gateway's robot reader never matched the writer of " << topic;
    }

    /// Makes a writer of `topic` on `robot` (the robot participant by default) and a base camp reader feeding
    /// `wan` (of `wan_topic`, when the gateway names it otherwise on the WAN), then waits until the gateway bridges
    /// the two. The writer, or nullptr with the failure recorded.
    template <typename PubSubType, typename Sample>
    fdds::DataWriter* bridge(const std::string& topic, const fdds::DataWriterQos& qos, CollectingReader<Sample>& wan,
                             TestParticipant* robot = nullptr, const std::string& wan_topic = {}) {
        TestParticipant& publisher = robot ? *robot : *robot_;
        auto& writer_matches = listener<MatchCounter>();
        auto* writer = publisher.make_writer(topic, fdds::TypeSupport(new PubSubType()), qos, &writer_matches);
        if (writer == nullptr) {
            ADD_FAILURE() << "cannot create a robot writer of " << topic;
            return nullptr;
        }
        const std::string& read = wan_topic.empty() ? topic : wan_topic;
        if (basecamp_->make_reader(read, fdds::TypeSupport(new PubSubType()), wan_reader_qos(*basecamp_), &wan) ==
            nullptr) {
            ADD_FAILURE() << "cannot create a base camp reader of " << read;
            return nullptr;
        }
        wait_for_bridge(topic, writer_matches, wan.matched);
        return HasFatalFailure() ? nullptr : writer;
    }

    /// Rows of the on-robot log `log_file` logged with `reason`.
    static std::int64_t logged_with_reason(const std::string& log_file, const std::string& reason) {
        sqlite3* db = nullptr;
        EXPECT_EQ(sqlite3_open_v2(log_file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
        sqlite3_stmt* stmt = nullptr;
        EXPECT_EQ(sqlite3_prepare_v2(db, "SELECT COUNT(*) FROM dropped_samples WHERE reason = ?1", -1, &stmt, nullptr),
                  SQLITE_OK);
        sqlite3_bind_text(stmt, 1, reason.c_str(), -1, SQLITE_TRANSIENT);
        EXPECT_EQ(sqlite3_step(stmt), SQLITE_ROW);
        const std::int64_t n = sqlite3_column_int64(stmt, 0);
        sqlite3_finalize(stmt);
        sqlite3_close(db);
        return n;
    }

    void expect_balanced() const {
        const core::TopicCounters c = gateway_->total_counters();
        EXPECT_EQ(c.received, c.forwarded + c.queued + c.dropped_total())
            << "received " << c.received << " forwarded " << c.forwarded << " queued " << c.queued << " dropped "
            << c.dropped_total();
    }

    static eprosima::fastrtps::Time_t wall_stamp(base::WallTime t) { return passthrough::to_dds_time(t); }

    base::SystemClock clock_;
    TestDomains domains_;
    std::string topic_prefix_;
    PublisherWatcher watcher_;
    std::unique_ptr<TestParticipant> robot_;
    std::unique_ptr<TestParticipant> basecamp_;
    std::unique_ptr<Gateway> gateway_;
    std::vector<std::string> files_;
    std::vector<std::shared_ptr<void>> listeners_;
};

}  // namespace tgw::test
