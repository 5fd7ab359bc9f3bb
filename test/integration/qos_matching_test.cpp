// Any base-camp reader that would match the robot's publisher matches the gateway: real Fast DDS participants,
// with the QoS programs use by default (ROS 2's reliable readers, Fast DDS's transient-local writers), and
// every case checks what arrives, not only that endpoints matched.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "KeyedReadingPubSubTypes.h"
#include "PaperWorkloadPubSubTypes.h"
#include "RosStringPubSubTypes.h"
#include "test/integration/gateway_fixture.hpp"

namespace tgw::test {
namespace {

using Offer = passthrough::OfferedQos;

class QosMatchingTest : public GatewayIntegrationTest {
  protected:
    /// What a robot process offers: Fast DDS's default writer (reliable, transient local) with room for bursts.
    fdds::DataWriterQos writer_qos(bool reliable, bool transient_local, int depth = 100) const {
        fdds::DataWriterQos q = robot_->default_writer_qos();
        q.reliability().kind = reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
        q.durability().kind = transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
        q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        q.history().depth = depth;
        return q;
    }

    /// What a base-camp program asks for: ROS 2's default is reliable, volatile, keep last 10.
    fdds::DataReaderQos reader_qos(bool reliable, bool transient_local, int depth = 100) const {
        fdds::DataReaderQos q = basecamp_->default_reader_qos();
        q.reliability().kind = reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
        q.durability().kind = transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
        q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        q.history().depth = depth;
        return q;
    }

    template <typename PubSubType>
    fdds::DataWriter* robot_writer(const std::string& topic, const fdds::DataWriterQos& qos,
                                   const std::vector<std::string>& partitions = {}) {
        auto& matches = listener<MatchCounter>();
        auto* writer = robot_->make_writer(topic, fdds::TypeSupport(new PubSubType()), qos, &matches, partitions);
        EXPECT_NE(writer, nullptr) << "cannot create the robot writer of " << topic;
        if (writer != nullptr) {
            EXPECT_TRUE(gateway_->wait_for_topic(topic, MATCH_TIMEOUT)) << topic << " was never bridged";
            EXPECT_TRUE(wait_until([&] { return matches.matched.load() > 0; }, MATCH_TIMEOUT))
                << "the gateway never matched the robot writer of " << topic;
        }
        return writer;
    }

    template <typename PubSubType, typename Sample>
    bool basecamp_reader(const std::string& topic, const fdds::DataReaderQos& qos, CollectingReader<Sample>& into,
                         const std::vector<std::string>& partitions = {}) {
        if (basecamp_->make_reader(topic, fdds::TypeSupport(new PubSubType()), qos, &into, partitions) == nullptr) {
            ADD_FAILURE() << "cannot create the base-camp reader of " << topic;
            return false;
        }
        return true;
    }

    /// Waits until `reader` and the gateway's WAN writer of `topic` know each other: a volatile writer does not
    /// send what it wrote before it matched the reader.
    template <typename Sample>
    void wait_until_linked(const std::string& topic, const CollectingReader<Sample>& reader) {
        ASSERT_TRUE(wait_until([&] { return reader.matched.load() > 0; }, MATCH_TIMEOUT))
            << "the base camp's reader never matched the gateway's writer of " << topic;
        const core::TopicId id = gateway_->find_topic(topic)->id;
        ASSERT_TRUE(wait_until([&] { return gateway_->wan_matched_readers(id) > 0; }, MATCH_TIMEOUT))
            << "the gateway's WAN writer never matched the base camp's reader of " << topic;
        ASSERT_TRUE(wait_until([&] { return gateway_->robot_matched_writers(id) > 0; }, MATCH_TIMEOUT))
            << "the gateway's robot reader never matched the writer of " << topic;
    }

    /// A base-camp reader asking `reader`, then a robot writer offering `writer`, on `topic`; once the gateway
    /// links the two, paper messages 0 .. count-1 are written and each is expected at the base camp once.
    void expect_paper_messages_cross(const std::string& topic, const fdds::DataWriterQos& writer,
                                     const fdds::DataReaderQos& reader, std::uint64_t count) {
        auto& wan = listener<CollectingReader<idl::PaperMessage>>();
        ASSERT_TRUE(basecamp_reader<idl::PaperMessagePubSubType>(topic, reader, wan));
        auto* robot = robot_writer<idl::PaperMessagePubSubType>(topic, writer);
        ASSERT_NE(robot, nullptr);
        wait_until_linked(topic, wan);
        ASSERT_FALSE(HasFatalFailure());
        expect_numbered_samples_cross(robot, wan, count);
    }

    /// Writes paper messages 0 .. count-1 and expects each at the base camp once, in order.
    void expect_numbered_samples_cross(fdds::DataWriter* writer, const CollectingReader<idl::PaperMessage>& wan,
                                       std::uint64_t count) {
        for (std::uint64_t i = 0; i < count; ++i) {
            auto m = paper_message(i);
            ASSERT_TRUE(writer->write(&m));
        }
        EXPECT_TRUE(wait_until([&] { return wan.count() >= count; })) << "got " << wan.count() << " of " << count;
        EXPECT_EQ(numbers(wan), range(0, count));
    }

    /// A latched keyed topic as /tf_static's (reliable, transient local, keep last 1, no Lifespan) with a camp
    /// reader `early`, and two rounds of sensors 1, 2 and 3 (value 0, then 1) that reached it.
    void write_two_rounds_of_three_instances(const std::string& topic, CollectingReader<idl::KeyedReading>& early) {
        auto* writer = robot_writer<idl::KeyedReadingPubSubType>(topic, writer_qos(true, true, 1));
        ASSERT_NE(writer, nullptr);
        ASSERT_TRUE(basecamp_reader<idl::KeyedReadingPubSubType>(topic, reader_qos(true, true), early));
        wait_until_linked(topic, early);
        ASSERT_FALSE(HasFatalFailure());
        for (std::uint32_t round = 0; round < 2; ++round) {
            for (std::uint32_t sensor : {1u, 2u, 3u}) {
                idl::KeyedReading r;
                r.sensor_id(sensor);
                r.value(round);
                ASSERT_TRUE(writer->write(&r));
            }
        }
        ASSERT_TRUE(wait_until([&] { return early.count() >= 6; })) << "got " << early.count();
    }

    static idl::PaperMessage paper_message(std::uint64_t n) {
        idl::PaperMessage m;
        m.generated_ns(n);
        m.data(std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(n)));
        return m;
    }

    /// The generated_ns of every sample received, in order.
    static std::vector<std::uint64_t> numbers(const CollectingReader<idl::PaperMessage>& reader) {
        std::vector<std::uint64_t> out;
        for (const auto& r : reader.received()) {
            out.push_back(r.data.generated_ns());
        }
        return out;
    }

    static std::vector<std::uint64_t> range(std::uint64_t first, std::uint64_t count) {
        std::vector<std::uint64_t> out;
        for (std::uint64_t i = 0; i < count; ++i) {
            out.push_back(first + i);
        }
        return out;
    }
};

struct MatrixCase {
    const char* name;
    bool writer_reliable;
    bool writer_transient_local;
    bool reader_reliable;
    bool reader_transient_local;
};

class QosMatrixTest : public QosMatchingTest, public ::testing::WithParamInterface<MatrixCase> {};

// Every pairing DDS itself would match: the reader asks for no more than the publisher offers.
TEST_P(QosMatrixTest, ABaseCampReaderGetsEverySampleOfAPublisherItWouldMatchDirectly) {
    const MatrixCase c = GetParam();
    start_gateway(config());
    const std::string topic = topic_prefix_ + c.name;
    expect_paper_messages_cross(topic, writer_qos(c.writer_reliable, c.writer_transient_local),
                                reader_qos(c.reader_reliable, c.reader_transient_local), 50);
    ASSERT_FALSE(HasFatalFailure());
    const auto bridged = gateway_->find_topic(topic);
    ASSERT_EQ(bridged->lanes.size(), 1u);
    EXPECT_EQ(bridged->lanes[0].reliable, c.writer_reliable);
    EXPECT_EQ(bridged->lanes[0].transient_local, c.writer_transient_local);
    expect_balanced();
}

INSTANTIATE_TEST_SUITE_P(Pairings, QosMatrixTest,
                         ::testing::Values(MatrixCase{"reliable_to_reliable", true, false, true, false},
                                           MatrixCase{"reliable_to_best_effort", true, false, false, false},
                                           MatrixCase{"best_effort_to_best_effort", false, false, false, false},
                                           MatrixCase{"latched_to_reliable_volatile", true, true, true, false},
                                           MatrixCase{"latched_to_latched", true, true, true, true}),
                         [](const ::testing::TestParamInfo<MatrixCase>& info) { return std::string(info.param.name); });

TEST_F(QosMatchingTest, TheWanWriterOffersWhatThePublisherOffered) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "mirrored";
    fdds::DataWriterQos q = writer_qos(true, true);
    q.ownership().kind = fdds::EXCLUSIVE_OWNERSHIP_QOS;
    q.ownership_strength().value = 42;
    q.deadline().period = eprosima::fastrtps::Duration_t(2, 0);
    ASSERT_NE(robot_writer<idl::PaperMessagePubSubType>(topic, q, {"site7"}), nullptr);

    PublisherWatcher::Seen seen;
    ASSERT_TRUE(wait_until([&] { return watcher_.find(topic, seen); }, MATCH_TIMEOUT));
    EXPECT_EQ(seen.reliability, fdds::RELIABLE_RELIABILITY_QOS);
    EXPECT_EQ(seen.durability, fdds::TRANSIENT_LOCAL_DURABILITY_QOS);
    EXPECT_EQ(seen.ownership, fdds::EXCLUSIVE_OWNERSHIP_QOS);
    EXPECT_EQ(seen.ownership_strength, 42u);
    EXPECT_EQ(seen.partitions, std::vector<std::string>{"site7"});
}

class HeartbeatSpacingTest : public QosMatchingTest, public ::testing::WithParamInterface<std::uint32_t> {};

// A reliable WAN writer's HEARTBEATs ride in the samples' messages and are charged as they leave: one in every
// message with spacing 0 (Fast DDS's default), one per `spacing` bytes of the writer's messages otherwise.
TEST_P(HeartbeatSpacingTest, AReliableWriterSendsAndIsChargedTheHeartbeatsItsSpacingAllows) {
    const std::uint32_t spacing = GetParam();
    auto c = config();
    c.wan_heartbeat_bytes = spacing;
    start_gateway(c);
    const std::string topic = topic_prefix_ + "heartbeats";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_TRUE(basecamp_reader<idl::PaperMessagePubSubType>(topic, reader_qos(true, false), wan));
    auto* robot = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(true, false));
    ASSERT_NE(robot, nullptr);
    wait_until_linked(topic, wan);
    ASSERT_FALSE(HasFatalFailure());

    // Discovery's first announcements (repeated at start) are charged too: let them end.
    std::uint64_t before = gateway_->unscheduled_wire_bytes();
    for (int quiet_checks = 0; quiet_checks < 20; ++quiet_checks) {
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        const std::uint64_t now = gateway_->unscheduled_wire_bytes();
        if (now == before) {
            break;
        }
        before = now;
    }
    constexpr std::uint64_t SAMPLES = 100;
    constexpr std::uint64_t HEARTBEAT_BYTES = 32;
    for (std::uint64_t i = 0; i < SAMPLES; ++i) {
        auto m = paper_message(i);
        ASSERT_TRUE(robot->write(&m));
        // One WAN write per sample, as at the paper's rates.
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_TRUE(wait_until([&] { return wan.count() >= SAMPLES; })) << "got " << wan.count();
    EXPECT_EQ(numbers(wan), range(0, SAMPLES));
    const std::uint64_t charged = gateway_->unscheduled_wire_bytes() - before;
    if (spacing == 0) {
        EXPECT_GE(charged, SAMPLES * HEARTBEAT_BYTES) << "a HEARTBEAT in every sample's message, each charged";
    } else {
        // A 41-byte sample's message is about 150 bytes: one HEARTBEAT per 7 or so, and little else.
        EXPECT_GT(charged, 0u);
        EXPECT_LT(charged, SAMPLES * HEARTBEAT_BYTES / 2) << "HEARTBEATs are spaced by " << spacing << " bytes";
    }
}

INSTANTIATE_TEST_SUITE_P(Spacing, HeartbeatSpacingTest, ::testing::Values(0u, dds::DEFAULT_HEARTBEAT_SPACING_BYTES),
                         [](const ::testing::TestParamInfo<std::uint32_t>& info) {
                             return info.param == 0 ? std::string("every_sample") : std::string("default");
                         });

// The base camp sees a robot publisher go as it would see it go without the gateway: the lane's WAN writer is
// deleted once what the publisher sent is past its TTL; the next publisher of that QoS brings the lane back.
TEST_F(QosMatchingTest, ALaneIsRetiredATtlAfterItsLastPublisherLeftAndComesBackWithTheNext) {
    auto c = config();
    c.default_ttl = 1s;
    start_gateway(c);
    const std::string topic = topic_prefix_ + "coming_and_going";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_TRUE(basecamp_reader<idl::PaperMessagePubSubType>(topic, reader_qos(true, false), wan));
    auto* first = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(true, false));
    ASSERT_NE(first, nullptr);
    wait_until_linked(topic, wan);
    ASSERT_FALSE(HasFatalFailure());
    expect_numbered_samples_cross(first, wan, 5);

    const auto left = std::chrono::steady_clock::now();
    ASSERT_EQ(const_cast<fdds::Publisher*>(first->get_publisher())->delete_datawriter(first), ReturnCode_t::RETCODE_OK);
    ASSERT_TRUE(wait_until([&] { return wan.matched.load() == 0; }, 15s))
        << "the base camp still matches the WAN writer of a topic whose publisher left";
    EXPECT_GE(std::chrono::steady_clock::now() - left, c.default_ttl) << "retired before its samples' TTL";
    // Its only lane gone, nothing of it was queued: the topic is retired with it, bridge and all.
    EXPECT_TRUE(wait_until([&] { return !gateway_->find_topic(topic); }, 5s))
        << "the topic is still bridged with no lane left";

    auto* second = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(true, false));
    ASSERT_NE(second, nullptr);
    wait_until_linked(topic, wan);
    ASSERT_FALSE(HasFatalFailure());
    for (std::uint64_t i = 5; i < 10; ++i) {
        auto m = paper_message(i);
        ASSERT_TRUE(second->write(&m));
    }
    EXPECT_TRUE(wait_until([&] { return wan.count() >= 10; })) << "got " << wan.count() << " of 10";
    EXPECT_EQ(numbers(wan), range(0, 10));
    const auto back = gateway_->find_topic(topic);
    EXPECT_EQ(back->lanes.size(), 1u) << "a new bridge, with one lane";
    EXPECT_EQ(back->live, std::vector<bool>{true});
    expect_balanced();
}

TEST_F(QosMatchingTest, AnExclusiveOwnershipReaderGetsTheSamples) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "exclusive";
    fdds::DataWriterQos wq = writer_qos(true, false);
    wq.ownership().kind = fdds::EXCLUSIVE_OWNERSHIP_QOS;
    wq.ownership_strength().value = 5;
    fdds::DataReaderQos rq = reader_qos(true, false);
    rq.ownership().kind = fdds::EXCLUSIVE_OWNERSHIP_QOS;
    expect_paper_messages_cross(topic, wq, rq, 10);
}

TEST_F(QosMatchingTest, APartitionedPublisherReachesReadersOfItsPartitionOnly) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "partitioned";
    auto& in_site = listener<CollectingReader<idl::PaperMessage>>();
    auto& outside = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_TRUE(basecamp_reader<idl::PaperMessagePubSubType>(topic, reader_qos(true, false), in_site, {"site7"}));
    ASSERT_TRUE(basecamp_reader<idl::PaperMessagePubSubType>(topic, reader_qos(false, false), outside));
    auto* writer = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(true, false), {"site7"});
    ASSERT_NE(writer, nullptr);
    wait_until_linked(topic, in_site);
    ASSERT_FALSE(HasFatalFailure());

    expect_numbered_samples_cross(writer, in_site, 20);
    EXPECT_EQ(outside.count(), 0u) << "a reader outside the partition got samples of it";
    EXPECT_EQ(outside.matched.load(), 0);
}

TEST_F(QosMatchingTest, ReliableAndBestEffortPublishersOfOneTopicEachArriveOnce) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "mixed";
    auto& best_effort = listener<CollectingReader<idl::PaperMessage>>();
    auto& reliable = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_TRUE(basecamp_reader<idl::PaperMessagePubSubType>(topic, reader_qos(false, false), best_effort));
    ASSERT_TRUE(basecamp_reader<idl::PaperMessagePubSubType>(topic, reader_qos(true, false), reliable));
    // The reliable one first: a reader copied from it would never match the best-effort one.
    auto* strong = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(true, false));
    ASSERT_NE(strong, nullptr);
    auto& weak_matches = listener<MatchCounter>();
    auto* weak = robot_->make_writer(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                     writer_qos(false, false), &weak_matches);
    ASSERT_NE(weak, nullptr);
    ASSERT_TRUE(wait_until([&] { return weak_matches.matched.load() > 0; }, MATCH_TIMEOUT))
        << "the gateway never matched the best-effort publisher";
    ASSERT_TRUE(wait_until([&] { return gateway_->find_topic(topic)->lanes.size() == 2; }, MATCH_TIMEOUT));
    ASSERT_TRUE(
        wait_until([&] { return best_effort.matched.load() == 2 && reliable.matched.load() == 1; }, MATCH_TIMEOUT))
        << "best-effort reader matched " << best_effort.matched.load() << " writers, reliable "
        << reliable.matched.load();
    const core::TopicId id = gateway_->find_topic(topic)->id;
    ASSERT_TRUE(wait_until([&] { return gateway_->wan_matched_readers(id) == 3; }, MATCH_TIMEOUT))
        << "the gateway's two WAN writers matched " << gateway_->wan_matched_readers(id) << " readers, not 3";

    for (std::uint64_t i = 0; i < 20; ++i) {
        auto a = paper_message(i);
        auto b = paper_message(1000 + i);
        ASSERT_TRUE(strong->write(&a));
        ASSERT_TRUE(weak->write(&b));
    }
    ASSERT_TRUE(wait_until([&] { return best_effort.count() >= 40 && reliable.count() >= 20; }))
        << "best effort got " << best_effort.count() << " of 40, reliable " << reliable.count() << " of 20";
    std::multiset<std::uint64_t> got;
    for (std::uint64_t n : numbers(best_effort)) {
        got.insert(n);
    }
    std::multiset<std::uint64_t> expected;
    for (std::uint64_t i = 0; i < 20; ++i) {
        expected.insert(i);
        expected.insert(1000 + i);
    }
    EXPECT_EQ(got, expected) << "each sample once, from both publishers";
    EXPECT_EQ(numbers(reliable), range(0, 20)) << "the reliable reader gets the reliable publisher's samples";
    EXPECT_EQ(gateway_->total_counters().forwarded, 40u) << "a sample crossed twice";
}

TEST_F(QosMatchingTest, ALateJoinerToALatchedTopicGetsTheLastSampleOfEachInstanceAfterTheTtl) {
    GatewayConfig c = config();
    c.default_ttl = 300ms;
    start_gateway(c);
    const std::string topic = topic_prefix_ + "latched";
    auto& early = listener<CollectingReader<idl::KeyedReading>>();
    ASSERT_NO_FATAL_FAILURE(write_two_rounds_of_three_instances(topic, early));
    const auto written = std::chrono::steady_clock::now();
    ASSERT_TRUE(wait_until([&] { return std::chrono::steady_clock::now() - written > 3 * c.default_ttl; }));

    const std::uint64_t unscheduled_before = gateway_->unscheduled_wire_bytes();
    auto& late = listener<CollectingReader<idl::KeyedReading>>();
    ASSERT_TRUE(basecamp_reader<idl::KeyedReadingPubSubType>(topic, reader_qos(true, true), late));
    std::set<fdds::InstanceHandle_t> early_instances;
    for (const auto& r : early.received()) {
        early_instances.insert(r.info.instance_handle);
    }
    EXPECT_EQ(early_instances.size(), 3u) << "the instances were not kept apart";
    EXPECT_EQ(gateway_->wan_writer_lifespan(gateway_->find_topic(topic)->id), std::nullopt)
        << "a latched sample must outlive the TTL in the WAN writer's history";
    ASSERT_TRUE(wait_until([&] { return late.count() >= 3; }))
        << "the late joiner got " << late.count() << " of 3"
        << (late.count() ? ", the first of sensor " + std::to_string(late.received()[0].data.sensor_id()) : "");
    std::map<std::uint32_t, double> last;
    for (const auto& r : late.received()) {
        last[r.data.sensor_id()] = r.data.value();
    }
    EXPECT_EQ(last, (std::map<std::uint32_t, double>{{1, 1.0}, {2, 1.0}, {3, 1.0}}));
    EXPECT_EQ(late.count(), 3u) << "only the last sample of each instance";
    // The history sent to the late joiner left outside the scheduler: it was charged to the budget.
    EXPECT_GE(gateway_->unscheduled_wire_bytes() - unscheduled_before, 3u * 100u);
}

// The WAN participant made anew on another address (a DHCP lease, a mesh radio): the latched writer's successor
// starts with no history of its own, so a camp program that joins after that must still get each instance's last
// sample, as it would have from the writer before.
TEST_F(QosMatchingTest, ALateJoinerAfterTheWanSideWasMadeAnewGetsTheLastSampleOfEachInstance) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "latched";
    auto& early = listener<CollectingReader<idl::KeyedReading>>();
    ASSERT_NO_FATAL_FAILURE(write_two_rounds_of_three_instances(topic, early));

    gateway_->rebind_wan("127.0.0.2");
    ASSERT_TRUE(wait_until([&] { return gateway_->wan_rebinds() == 1; }));
    auto& late = listener<CollectingReader<idl::KeyedReading>>();
    ASSERT_TRUE(basecamp_reader<idl::KeyedReadingPubSubType>(topic, reader_qos(true, true), late));
    ASSERT_TRUE(wait_until([&] { return late.count() >= 3; }))
        << "the late joiner got " << late.count() << " of 3 from the writer made anew";
    std::map<std::uint32_t, double> last;
    for (const auto& r : late.received()) {
        last[r.data.sensor_id()] = r.data.value();
    }
    EXPECT_EQ(last, (std::map<std::uint32_t, double>{{1, 1.0}, {2, 1.0}, {3, 1.0}}));
    EXPECT_EQ(late.count(), 3u) << "only the last sample of each instance";
    EXPECT_EQ(gateway_->total_counters().forwarded, 6u) << "given again to the successor, not forwarded again";
}

TEST_F(QosMatchingTest, AThousandInstancesInABurstArriveApartAndADisposeAndAnUnregisterFollow) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "instances";
    constexpr std::uint32_t KEYS = 1000;
    // Room for every instance on both ends (Fast DDS's default is 10).
    fdds::DataReaderQos rq = reader_qos(true, false, 1);
    rq.resource_limits().max_instances = KEYS;
    rq.resource_limits().max_samples = KEYS;
    rq.resource_limits().max_samples_per_instance = 1;
    fdds::DataWriterQos wq = writer_qos(true, false, 1);
    wq.resource_limits() = rq.resource_limits();
    wq.writer_data_lifecycle().autodispose_unregistered_instances = false;  // an unregister is not a dispose
    auto& wan = listener<CollectingReader<idl::KeyedReading>>();
    ASSERT_TRUE(basecamp_reader<idl::KeyedReadingPubSubType>(topic, rq, wan));
    auto* writer = robot_writer<idl::KeyedReadingPubSubType>(topic, wq);
    ASSERT_NE(writer, nullptr);
    wait_until_linked(topic, wan);
    ASSERT_FALSE(HasFatalFailure());

    std::map<std::uint32_t, fdds::InstanceHandle_t> robot_handles;
    for (std::uint32_t sensor = 0; sensor < KEYS; ++sensor) {
        idl::KeyedReading r;
        r.sensor_id(sensor);
        r.value(sensor * 0.5);
        robot_handles[sensor] = writer->register_instance(&r);
        ASSERT_EQ(writer->write(&r, robot_handles[sensor]), ReturnCode_t::RETCODE_OK);
    }
    ASSERT_TRUE(wait_until([&] { return wan.count() >= KEYS; }, std::chrono::seconds(20)))
        << "got " << wan.count() << " of " << KEYS;
    std::map<std::uint32_t, std::set<fdds::InstanceHandle_t>> handles;
    for (const auto& r : wan.received()) {
        handles[r.data.sensor_id()].insert(r.info.instance_handle);
    }
    ASSERT_EQ(handles.size(), KEYS);
    std::set<fdds::InstanceHandle_t> distinct;
    for (const auto& [sensor, h] : handles) {
        ASSERT_EQ(h.size(), 1u) << "sensor " << sensor << " arrived as several instances";
        EXPECT_EQ(*h.begin(), robot_handles[sensor]);
        distinct.insert(*h.begin());
    }
    EXPECT_EQ(distinct.size(), KEYS);

    idl::KeyedReading gone;
    gone.sensor_id(7);
    ASSERT_EQ(writer->dispose(&gone, robot_handles[7]), ReturnCode_t::RETCODE_OK);
    EXPECT_TRUE(wait_until([&] { return wan.disposed().count(robot_handles[7]) == 1; }))
        << "the dispose of sensor 7 never reached the base camp";
    EXPECT_EQ(wan.disposed().size(), 1u);

    // The robot's writer lets go of sensor 8: the gateway's WAN writer, its only writer at the base camp, does.
    idl::KeyedReading released;
    released.sensor_id(8);
    ASSERT_EQ(writer->unregister_instance(&released, robot_handles[8]), ReturnCode_t::RETCODE_OK);
    EXPECT_TRUE(wait_until([&] { return wan.unregistered().count(robot_handles[8]) == 1; }))
        << "the unregister of sensor 8 never reached the base camp";
    EXPECT_EQ(wan.unregistered().size(), 1u);
    EXPECT_EQ(wan.disposed().size(), 1u);

    expect_balanced();
}

TEST_F(QosMatchingTest, ARos2ChatterListenerWithDefaultQosGetsEveryMessage) {
    start_gateway(config());
    const std::string topic = "rt/chatter";  // the domains are this test's own
    // rclcpp's defaults on both sides: reliable, volatile, keep last 10.
    auto& listener_node = listener<CollectingReader<std_msgs::msg::dds_::String_>>();
    ASSERT_TRUE(
        basecamp_reader<std_msgs::msg::dds_::String_PubSubType>(topic, reader_qos(true, false, 10), listener_node));
    auto* talker = robot_writer<std_msgs::msg::dds_::String_PubSubType>(topic, writer_qos(true, false, 10));
    ASSERT_NE(talker, nullptr);
    wait_until_linked(topic, listener_node);
    ASSERT_FALSE(HasFatalFailure());

    constexpr std::size_t N = 200;
    for (std::size_t i = 0; i < N; ++i) {
        std_msgs::msg::dds_::String_ hello;
        hello.data("Hello World: " + std::to_string(i));
        ASSERT_TRUE(talker->write(&hello));
        std::this_thread::sleep_for(std::chrono::milliseconds(1));  // a talker publishes at a rate, not at once
    }
    ASSERT_TRUE(wait_until([&] { return listener_node.count() >= N; })) << "got " << listener_node.count();
    const auto got = listener_node.received();
    for (std::size_t i = 0; i < N; ++i) {
        EXPECT_EQ(got[i].data.data(), "Hello World: " + std::to_string(i));
    }
}

TEST_F(QosMatchingTest, AnXcdr2OnlyPublisherReachesAnXcdr2OnlyReader) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "xcdr2";
    fdds::DataWriterQos wq = writer_qos(true, false);
    wq.representation().m_value = {fdds::XCDR2_DATA_REPRESENTATION};
    fdds::DataReaderQos rq = reader_qos(true, false);
    rq.type_consistency().representation.m_value = {fdds::XCDR2_DATA_REPRESENTATION};
    expect_paper_messages_cross(topic, wq, rq, 10);
}

TEST_F(QosMatchingTest, AGatewayStartedAfterATransientLocalPublisherGetsItsHistory) {
    // The publisher wrote before the gateway (re)started: a transient-local lane's reader asks for its history.
    const std::string topic = topic_prefix_ + "history";
    auto& matches = listener<MatchCounter>();
    auto* writer = robot_->make_writer(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                       writer_qos(true, true, 5), &matches);
    ASSERT_NE(writer, nullptr);
    for (std::uint64_t i = 0; i < 3; ++i) {
        auto m = paper_message(i);
        ASSERT_TRUE(writer->write(&m));
    }
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_TRUE(basecamp_reader<idl::PaperMessagePubSubType>(topic, reader_qos(true, true), wan));

    start_gateway(config());
    ASSERT_TRUE(gateway_->wait_for_topic(topic, MATCH_TIMEOUT));
    const core::TopicId id = gateway_->find_topic(topic)->id;
    EXPECT_TRUE(wait_until([&] { return gateway_->counters(id).received >= 3; }))
        << "the gateway received " << gateway_->counters(id).received << " of the 3 samples written before it";
    // The WAN writer keeps the last sample for readers that come after it was written.
    EXPECT_TRUE(wait_until([&] {
        const auto got = numbers(wan);
        return !got.empty() && got.back() == 2;
    })) << "the base camp never got the last sample";
    expect_balanced();
}

}  // namespace
}  // namespace tgw::test
