// tm-basecamp relay between a gateway's WAN domain and a local domain: programs there with Fast DDS's defaults
// receive every topic, and a latched topic's late joiner is served by the relay, not the link. Real
// participants in one process: robot writer -> Gateway -> Relay -> local readers.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <map>
#include <memory>
#include <set>
#include <thread>

#include <sqlite3.h>
#include "AnnouncedTypesPubSubTypes.h"
#include "AnnouncedTypesTypeObject.h"
#include "KeyedReadingPubSubTypes.h"
#include "PaperWorkloadPubSubTypes.h"
#include "ReceiverReportPubSubTypes.h"
#include "RosStringPubSubTypes.h"
#include "basecamp/recording/sample_store.hpp"
#include "test/integration/relay_fixture.hpp"
#include "wire/receiver_report_topic.hpp"

namespace tgw::test {
namespace {

// Three programs on the camp's domain with their defaults: a Fast DDS reader with every default (best effort), a
// ROS 2 listener (reliable, keep last 10) on rt/chatter, and a reliable reader of a keyed topic.
TEST_F(RelayTest, DefaultReadersOnTheLocalDomainGetEveryTopicWithItsTimestampAndInstances) {
    start_gateway(config());
    start_relay();
    const std::string paper = topic_prefix_ + "paper";
    const std::string chatter = "rt/chatter";  // the domains are this test's own
    const std::string keyed = topic_prefix_ + "keyed";

    auto& paper_reader = listener<CollectingReader<idl::PaperMessage>>();
    local_reader<idl::PaperMessagePubSubType>(paper, local_->default_reader_qos(), paper_reader);
    fdds::DataReaderQos ros = local_->default_reader_qos();
    ros.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    ros.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    ros.history().depth = 10;
    auto& chatter_reader = listener<CollectingReader<std_msgs::msg::dds_::String_>>();
    local_reader<std_msgs::msg::dds_::String_PubSubType>(chatter, ros, chatter_reader);
    fdds::DataReaderQos keyed_qos = ros;
    keyed_qos.history().depth = 100;
    auto& keyed_reader = listener<CollectingReader<idl::KeyedReading>>();
    local_reader<idl::KeyedReadingPubSubType>(keyed, keyed_qos, keyed_reader);

    auto* paper_writer = robot_writer<idl::PaperMessagePubSubType>(paper, writer_qos(false));
    auto* chatter_writer = robot_writer<std_msgs::msg::dds_::String_PubSubType>(chatter, writer_qos(false, 10));
    auto* keyed_writer = robot_writer<idl::KeyedReadingPubSubType>(keyed, writer_qos(false));
    ASSERT_TRUE(paper_writer && chatter_writer && keyed_writer);
    for (auto* reader : {&paper_reader.matched, &chatter_reader.matched, &keyed_reader.matched}) {
        ASSERT_TRUE(wait_until([&] { return reader->load() > 0; }, 3 * MATCH_TIMEOUT))
            << "a local reader never matched the relay's writer";
    }
    // The relay's WAN readers match the gateway's writers a moment after its local writers exist, and a writer
    // sends a best-effort reader nothing before it has matched it from its own side.
    for (const std::string& topic : {paper, chatter, keyed}) {
        ASSERT_TRUE(wait_until([&] { return relay_->local_readers(topic) > 0; }, MATCH_TIMEOUT))
            << "the relay's local writer of " << topic << " never matched its reader";
        ASSERT_TRUE(wait_until([&] { return gateway_->wan_matched_readers(gateway_->find_topic(topic)->id) > 0; },
                               MATCH_TIMEOUT))
            << "the relay never matched the gateway's writer of " << topic;
    }

    constexpr std::uint32_t N = 20;
    std::map<std::uint64_t, eprosima::fastrtps::Time_t> stamps;
    std::map<std::uint32_t, fdds::InstanceHandle_t> robot_handles;
    for (std::uint32_t i = 0; i < N; ++i) {
        idl::PaperMessage m;
        m.generated_ns(i);
        m.data(std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
        stamps[i] = stamp_now();
        ASSERT_EQ(paper_writer->write_w_timestamp(&m, fdds::HANDLE_NIL, stamps[i]), ReturnCode_t::RETCODE_OK);
        std_msgs::msg::dds_::String_ hello;
        hello.data("hello world " + std::to_string(i));
        ASSERT_TRUE(chatter_writer->write(&hello));
        idl::KeyedReading r;
        r.sensor_id(i % 4);
        r.value(i);
        robot_handles[i % 4] = keyed_writer->register_instance(&r);
        ASSERT_EQ(keyed_writer->write(&r, robot_handles[i % 4]), ReturnCode_t::RETCODE_OK);
    }
    ASSERT_TRUE(wait_until([&] {
        return paper_reader.count() >= N && chatter_reader.count() >= N && keyed_reader.count() >= N;
    })) << "paper "
        << paper_reader.count() << ", chatter " << chatter_reader.count() << ", keyed " << keyed_reader.count()
        << " of " << N;

    for (const auto& r : paper_reader.received()) {
        const std::uint64_t i = r.data.generated_ns();
        EXPECT_EQ(r.data.data(), std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
        // RTPS carries fractions of 2^-32 s: equal to the nanosecond, give or take the rounding.
        EXPECT_NEAR(ns_of(r.info.source_timestamp), ns_of(stamps[i]), 2) << "sample " << i << " lost its timestamp";
    }
    std::vector<std::string> said;
    for (const auto& r : chatter_reader.received()) {
        said.push_back(r.data.data());
    }
    ASSERT_EQ(said.size(), N);
    EXPECT_EQ(said.front(), "hello world 0");
    EXPECT_EQ(said.back(), "hello world " + std::to_string(N - 1));
    std::map<std::uint32_t, std::set<fdds::InstanceHandle_t>> instances;
    for (const auto& r : keyed_reader.received()) {
        instances[r.data.sensor_id()].insert(r.info.instance_handle);
    }
    ASSERT_EQ(instances.size(), 4u);
    for (const auto& [sensor, handles] : instances) {
        ASSERT_EQ(handles.size(), 1u) << "sensor " << sensor << " arrived as several instances";
        EXPECT_EQ(*handles.begin(), robot_handles[sensor]);
    }
    EXPECT_EQ(gateway_->wan_participants(), 1u) << "the relay is the base camp's only participant on the WAN";
    EXPECT_EQ(relay_->relayed()[paper], N);
    expect_balanced();
}

// A program that joins the camp's domain after a latched topic was written gets it from the relay: nothing
// more crosses the link, and the gateway's writer still has the relay as its one reader.
TEST_F(RelayTest, ALateJoinerOnTheLocalDomainGetsALatchedTopicFromTheRelay) {
    start_gateway(config());
    start_relay();
    const std::string topic = topic_prefix_ + "latched";
    auto* writer = robot_writer<idl::KeyedReadingPubSubType>(topic, writer_qos(true, 1));
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(relay_matched_gateway_writer(topic)) << "the relay never matched the gateway's writer";
    for (std::uint32_t sensor = 1; sensor <= 3; ++sensor) {
        idl::KeyedReading r;
        r.sensor_id(sensor);
        r.value(sensor * 10.0);
        ASSERT_TRUE(writer->write(&r));
    }
    ASSERT_TRUE(wait_until([&] { return relay_->relayed()[topic] >= 3; })) << "relayed " << relay_->relayed()[topic];
    const core::TopicId id = gateway_->find_topic(topic)->id;
    const std::uint64_t forwarded = gateway_->counters(id).forwarded;

    fdds::DataReaderQos late_qos = local_->default_reader_qos();
    late_qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    late_qos.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
    auto& late = listener<CollectingReader<idl::KeyedReading>>();
    local_reader<idl::KeyedReadingPubSubType>(topic, late_qos, late);
    ASSERT_TRUE(wait_until([&] { return late.count() >= 3; })) << "the late joiner got " << late.count() << " of 3";
    std::map<std::uint32_t, double> last;
    for (const auto& r : late.received()) {
        last[r.data.sensor_id()] = r.data.value();
    }
    EXPECT_EQ(last, (std::map<std::uint32_t, double>{{1, 10.0}, {2, 20.0}, {3, 30.0}}));
    EXPECT_EQ(gateway_->counters(id).forwarded, forwarded) << "the late joiner cost the link a sample";
    EXPECT_EQ(gateway_->wan_matched_readers(id), 1) << "the late joiner reached the WAN";
    EXPECT_EQ(relay_->relayed()[topic], 3u);
}

// The relay's WAN participant made anew (its interface's address changed, a robot's name resolved to another): the
// camp's programs keep their readers matched to the same local writers, and samples reach them again once the
// gateway hears the new participant.
TEST_F(RelayTest, AWanParticipantMadeAnewKeepsTheCampsReadersMatchedToTheSameWriter) {
    /// A camp program's reader: the samples it took, and the writers it ever matched.
    struct CampReader final : fdds::DataReaderListener {
        void on_data_available(fdds::DataReader* reader) override {
            idl::KeyedReading data;
            fdds::SampleInfo info;
            while (reader->take_next_sample(&data, &info) == ReturnCode_t::RETCODE_OK)
                samples += info.valid_data ? 1 : 0;
        }
        void on_subscription_matched(fdds::DataReader*, const fdds::SubscriptionMatchedStatus& info) override {
            matched = info.current_count;
            writers_ever = info.total_count;
        }
        std::atomic<std::size_t> samples{0};
        std::atomic<std::int32_t> matched{0};
        std::atomic<std::int32_t> writers_ever{0};
    };
    start_gateway(config());
    start_relay();
    const std::string topic = topic_prefix_ + "remade";
    auto* writer = robot_writer<idl::KeyedReadingPubSubType>(topic, writer_qos(false));
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(relay_matched_gateway_writer(topic)) << "the relay never matched the gateway's writer";
    auto& camp = listener<CampReader>();
    ASSERT_NE(local_->make_reader(topic, fdds::TypeSupport(new idl::KeyedReadingPubSubType()),
                                  local_->default_reader_qos(), &camp),
              nullptr);
    ASSERT_TRUE(wait_until([&] { return camp.matched.load() == 1; }));
    const auto write = [&](std::uint32_t sensor) {
        idl::KeyedReading r;
        r.sensor_id(sensor);
        r.value(sensor * 10.0);
        return writer->write(&r);
    };
    for (std::uint32_t sensor = 1; sensor <= 3; ++sensor)
        ASSERT_TRUE(write(sensor));
    ASSERT_TRUE(wait_until([&] { return camp.samples.load() >= 3; })) << "got " << camp.samples.load() << " of 3";

    stop_relay_.store(true);
    relay_thread_.join();
    relay_->remake_wan(TestParticipant::wan_qos(domains_.wan_reader_port, domains_.gateway_wan_port));
    stop_relay_.store(false);
    relay_thread_ = std::thread([this] { relay_->run(std::chrono::minutes(5), stop_relay_); });

    // Until the gateway hears the new participant, what it writes finds no reader (or the old one): keep writing.
    ASSERT_TRUE(wait_until([&] { return write(4) && camp.samples.load() > 3; }, 20s))
        << "nothing reached the camp's reader after the WAN participant was made anew";
    EXPECT_EQ(camp.matched.load(), 1);
    EXPECT_EQ(camp.writers_ever.load(), 1) << "the camp's reader lost its writer and matched another";
    EXPECT_GE(relay_->relayed()[topic], 4u) << "the counts go on across the remake";
}

// In compact mode the unpacker goes with the WAN participant and comes back with the gateway's catalog: samples
// reach the camp's programs again (through a local writer made anew).
TEST_F(RelayTest, InCompactModeAWanParticipantMadeAnewRelaysAgain) {
    GatewayConfig c = config();
    c.compact_wan = true;
    start_gateway(c);
    start_relay();
    const std::string topic = topic_prefix_ + "remade";
    auto& camp = listener<CollectingReader<idl::PaperMessage>>();
    local_reader<idl::PaperMessagePubSubType>(topic, local_->default_reader_qos(), camp);
    auto* writer = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(false));
    ASSERT_NE(writer, nullptr);
    const auto write = [&] {
        idl::PaperMessage m;
        m.data(std::vector<std::uint8_t>(41, 7));
        return writer->write(&m);
    };
    ASSERT_TRUE(wait_until([&] { return write() && camp.count() > 0; }, 20s)) << "nothing before the remake";

    stop_relay_.store(true);
    relay_thread_.join();
    const std::uint64_t before = relay_->relayed()[topic];
    relay_->remake_wan(TestParticipant::wan_qos(domains_.wan_reader_port, domains_.gateway_wan_port));
    stop_relay_.store(false);
    relay_thread_ = std::thread([this] { relay_->run(std::chrono::minutes(5), stop_relay_); });
    EXPECT_EQ(relay_->relayed()[topic], before) << "the unpacker's counts kept";
    const std::size_t received = camp.count();
    ASSERT_TRUE(wait_until([&] { return write() && camp.count() > received; }, 20s))
        << "nothing reached the camp's reader after the WAN participant was made anew";
}

// A robot publisher's TypeObject reaches the camp's domain where it describes its type by itself: tm-basecamp echo
// and Foxglove there can decode the type. One that refers to other types stays behind; a reader whose type has a
// TypeObject still matches, and gets the samples.
TEST_F(RelayTest, TheRobotPublishersSelfContainedTypeObjectReachesTheCampsDomain) {
    registerAnnouncedTypesTypes();
    PublisherWatcher watcher;
    TestParticipant camp_tool(local_domain_, fdds::PARTICIPANT_QOS_DEFAULT, &watcher);
    ASSERT_TRUE(camp_tool.ok());
    start_gateway(config());
    start_relay();
    const std::string flat = topic_prefix_ + "flat";
    const std::string convoy = topic_prefix_ + "convoy";
    auto* flat_writer = robot_writer<tgw_test::FlatReadingPubSubType>(flat, writer_qos(false));
    auto* convoy_writer = robot_writer<tgw_test::ConvoyPubSubType>(convoy, writer_qos(false));
    ASSERT_NE(flat_writer, nullptr);
    ASSERT_NE(convoy_writer, nullptr);

    PublisherWatcher::Seen flat_seen;
    PublisherWatcher::Seen convoy_seen;
    ASSERT_TRUE(wait_until([&] { return watcher.find(flat, flat_seen) && watcher.find(convoy, convoy_seen); }))
        << "the relay's writers never appeared on the camp's domain";
    ASSERT_NE(flat_seen.type_object, nullptr) << "the relay's writer of " << flat << " announced no TypeObject";
    EXPECT_TRUE(*flat_seen.type_object == *tgw_test::GetFlatReadingObject(true));
    EXPECT_EQ(convoy_seen.type_object, nullptr);

    fdds::DataReaderQos qos = camp_tool.default_reader_qos();
    qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    auto& received = listener<CollectingReader<tgw_test::FlatReading>>();
    ASSERT_NE(camp_tool.make_reader(flat, fdds::TypeSupport(new tgw_test::FlatReadingPubSubType()), qos, &received),
              nullptr);
    ASSERT_TRUE(wait_until([&] {
        tgw_test::FlatReading reading;
        reading.sensor_id(7);
        flat_writer->write(&reading);
        return received.count() > 0;
    })) << "a reader with the type's TypeObject received nothing";
    EXPECT_EQ(received.received().front().data.sensor_id(), 7u);
}

// relay --out records what it takes off the WAN, as record does, and the relay, the camp's one WAN participant,
// reports to the gateway what arrived.
TEST_F(RelayTest, RecordsWhatItRelaysAndReportsItToTheGateway) {
    GatewayConfig c = config();
    c.receiver_reports = true;
    start_gateway(c);
    const std::string path = temp_file(".db");
    auto store = std::make_unique<basecamp::SampleStore>(path, "--out", 50);
    start_relay(store.get(), 200ms);
    const std::string topic = topic_prefix_ + "recorded";
    auto* writer = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(false));
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(relay_matched_gateway_writer(topic)) << "the relay never matched the gateway's writer";

    constexpr std::uint64_t N = 10;
    for (std::uint64_t i = 0; i < N; ++i) {
        idl::PaperMessage m;
        m.generated_ns(i);
        m.data(std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
        ASSERT_TRUE(writer->write(&m));
    }
    ASSERT_TRUE(wait_until([&] { return relay_->relayed()[topic] >= N; })) << "relayed " << relay_->relayed()[topic];
    ASSERT_TRUE(wait_until([&] {
        const auto report = gateway_->receiver_report();
        return report && report->received_samples >= N;
    })) << "the gateway never heard from the relay";
    EXPECT_EQ(gateway_->receiver_report()->lost_samples, 0u);

    store->flush();
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
    sqlite3_stmt* stmt = nullptr;
    ASSERT_EQ(
        sqlite3_prepare_v2(db,
                           "SELECT COUNT(*), MIN(length(payload)), (SELECT COUNT(*) FROM topics WHERE topic = ?1) "
                           "FROM samples WHERE topic = ?1 AND source_ns > 0",
                           -1, &stmt, nullptr),
        SQLITE_OK);
    sqlite3_bind_text(stmt, 1, topic.c_str(), -1, SQLITE_TRANSIENT);
    ASSERT_EQ(sqlite3_step(stmt), SQLITE_ROW);
    EXPECT_EQ(static_cast<std::uint64_t>(sqlite3_column_int64(stmt, 0)), N);
    EXPECT_GT(sqlite3_column_int64(stmt, 1), 41) << "the payload as received, encapsulation included";
    EXPECT_EQ(sqlite3_column_int64(stmt, 2), 1);
    sqlite3_finalize(stmt);
    sqlite3_close(db);
    stop_relay_.store(true);
    relay_thread_.join();
    relay_.reset();
}

// A camp tool's reliable reader (ROS 2's default) of the receiver reports, on a participant of its own: the
// reporter's writer must be reliable for it to match.
TEST_F(RelayTest, AReliableReaderOfACampToolGetsTheReceiverReports) {
    start_gateway(config());
    start_relay(nullptr, 200ms);
    TestParticipant tool(domains_.wan, TestParticipant::wan_qos(base::metatraffic_unicast_port(domains_.wan, 63),
                                                                domains_.wan_reader_port));
    ASSERT_TRUE(tool.ok());
    fdds::DataReaderQos qos = tool.default_reader_qos();
    qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    CollectingReader<idl::ReceiverReport> reports;
    ASSERT_NE(tool.make_reader(wire::RECEIVER_REPORT_TOPIC, fdds::TypeSupport(new idl::ReceiverReportPubSubType()), qos,
                               &reports),
              nullptr);
    const std::string topic = topic_prefix_ + "reported";
    auto* writer = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(false));
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(relay_matched_gateway_writer(topic)) << "the relay never matched the gateway's writer";
    idl::PaperMessage m;
    m.data(std::vector<std::uint8_t>(41, 7));
    ASSERT_TRUE(writer->write(&m));
    ASSERT_TRUE(wait_until(
        [&] {
            const auto got = reports.received();
            return std::any_of(got.begin(), got.end(), [](const auto& r) { return r.data.received_samples() > 0; });
        },
        20s))
        << "no receiver report reached the tool (" << reports.count() << " without a sample)";
    stop_relay_.store(true);
    relay_thread_.join();
    relay_.reset();
}

}  // namespace
}  // namespace tgw::test
