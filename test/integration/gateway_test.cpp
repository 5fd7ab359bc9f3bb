// Real Fast DDS participants in one process: robot domain -> Gateway -> WAN domain over loopback UDP.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <thread>

#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>

#include "KeyedReadingPubSubTypes.h"
#include "PaperWorkloadPubSubTypes.h"
#include "RosStringPubSubTypes.h"
#include "base/clock.hpp"
#include "basecamp/capture/delivery_tally.hpp"
#include "basecamp/capture/receiver_reporter.hpp"
#include "core/wire_model.hpp"
#include "gateway/dds/gateway.hpp"
#include "passthrough/dds_time.hpp"
#include "test/integration/error_log_counter.hpp"
#include "test/integration/gateway_fixture.hpp"
#include "test/integration/opaque_type.hpp"

namespace tgw::test {
namespace {

using namespace std::chrono_literals;
using dds::Gateway;
using dds::GatewayConfig;

TEST_F(GatewayIntegrationTest, ForwardsPaperMessagesWithPayloadAndSourceTimestamp) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "paper_A";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_, 2s), wan);
    ASSERT_NE(writer, nullptr);

    constexpr int N = 10;
    std::vector<eprosima::fastrtps::Time_t> stamps;
    for (int i = 0; i < N; ++i) {
        idl::PaperMessage msg;
        msg.generated_ns(static_cast<std::uint64_t>(1000 + i));
        msg.data(std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
        stamps.push_back(wall_stamp(clock_.wall_now() - std::chrono::milliseconds(5 * (N - i))));
        ASSERT_EQ(writer->write_w_timestamp(&msg, fdds::HANDLE_NIL, stamps.back()), ReturnCode_t::RETCODE_OK);
    }
    ASSERT_TRUE(wait_until([&] { return wan.count() >= N; })) << "got " << wan.count() << " of " << N;
    const auto got = wan.received();
    for (int i = 0; i < N; ++i) {
        EXPECT_EQ(got[i].data.generated_ns(), static_cast<std::uint64_t>(1000 + i));
        EXPECT_EQ(got[i].data.data(), std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
        EXPECT_EQ(got[i].info.source_timestamp.seconds(), stamps[i].seconds);
        EXPECT_EQ(got[i].info.source_timestamp.nanosec(), stamps[i].nanosec);
    }
    const auto bridged = gateway_->find_topic(topic);
    ASSERT_TRUE(bridged);
    EXPECT_EQ(bridged->type_name, "tgw::idl::PaperMessage");
    EXPECT_FALSE(bridged->keyed);
    EXPECT_EQ(gateway_->counters(bridged->id).forwarded, static_cast<std::uint64_t>(N));
    expect_balanced();
}

/// While the WAN interface is down (sensor::LinkStateWatch says so), the budget is 0 whatever the rate: samples
/// wait, and go to the on-robot log as their TTL passes; none is written and counted as forwarded. Once it is up,
/// what still has time goes first.
TEST_F(GatewayIntegrationTest, WhileTheWanLinkIsDownSamplesWaitOrExpireAndNoneIsWritten) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "link_down";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_, 1s), wan);
    ASSERT_NE(writer, nullptr);
    const core::TopicId id = gateway_->find_topic(topic)->id;

    gateway_->set_wan_link_up(false);
    EXPECT_FALSE(gateway_->wan_link_up());
    EXPECT_EQ(gateway_->rate_bps(), 0.0);
    idl::PaperMessage msg;
    msg.data(std::vector<std::uint8_t>(41, 1));
    ASSERT_TRUE(writer->write(&msg));
    ASSERT_TRUE(wait_until([&] { return gateway_->counters(id).dropped_for(core::DropReason::expired) == 1; }))
        << "the sample neither expired nor left";
    EXPECT_EQ(gateway_->counters(id).forwarded, 0u);
    EXPECT_EQ(wan.count(), 0u);

    ASSERT_TRUE(writer->write(&msg));  // waits for the link, which comes back within its TTL
    ASSERT_TRUE(wait_until([&] { return gateway_->queued_samples() == 1; }));
    gateway_->set_wan_link_up(true);
    EXPECT_GT(gateway_->rate_bps(), 0.0);
    ASSERT_TRUE(wait_until([&] { return wan.count() == 1; })) << "the waiting sample did not leave";
    EXPECT_EQ(gateway_->counters(id).forwarded, 1u);
    expect_balanced();
}

// A DHCP lease or a mesh radio gives the WAN interface another address: the WAN participant is made anew on it, the
// bridged topic's writer gets its successor there, and the base camp hears the new participant (loopback has every
// 127.x address).
TEST_F(GatewayIntegrationTest, MadeAnewOnAnotherAddressTheWanSideCarriesOnFromANewParticipant) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "rebind";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    idl::PaperMessage msg;
    msg.data(std::vector<std::uint8_t>(41, 1));
    ASSERT_TRUE(writer->write(&msg));
    ASSERT_TRUE(wait_until([&] { return wan.count() == 1; }));
    const auto before = gateway_->wan_guid_prefix();

    gateway_->rebind_wan("127.0.0.2");
    ASSERT_TRUE(wait_until([&] { return gateway_->wan_rebinds() == 1; }));
    EXPECT_EQ(gateway_->wan_interface_address(), "127.0.0.2");
    EXPECT_NE(gateway_->wan_guid_prefix(), before);
    EXPECT_GT(gateway_->rate_bps(), 0.0);
    // Until the base camp has matched the successor, a sample may go to the log as no_reader: write until one
    // arrives.
    const auto give_up = std::chrono::steady_clock::now() + MATCH_TIMEOUT;
    while (wan.count() < 2 && std::chrono::steady_clock::now() < give_up) {
        msg.sequence_number(msg.sequence_number() + 1);
        ASSERT_TRUE(writer->write(&msg));
        wait_until([&] { return wan.count() >= 2; }, 200ms);
    }
    ASSERT_GE(wan.count(), 2u) << "nothing arrived from the participant made anew";
    gateway_->rebind_wan("127.0.0.2");  // the same address again: nothing to do
    std::this_thread::sleep_for(100ms);
    EXPECT_EQ(gateway_->wan_rebinds(), 1u);
    EXPECT_GT(gateway_->rate_bps(), 0.0);
    expect_balanced();
}

/// Large samples cross intact whatever the WAN's datagram limit: as DATA_FRAGs of one Ethernet frame each by
/// default, or in one datagram with --wan-max-datagram 65500.
class LargeSampleTest : public GatewayIntegrationTest, public ::testing::WithParamInterface<std::size_t> {};

TEST_P(LargeSampleTest, ArrivesIntact) {
    GatewayConfig c = config();
    c.scheduler.wire = core::WireModel::for_max_datagram(GetParam());
    start_gateway(c);
    const std::string topic = topic_prefix_ + "large";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);

    constexpr int N = 5;
    constexpr std::size_t BYTES = 60'000;
    for (int i = 0; i < N; ++i) {
        idl::PaperMessage msg;
        msg.sequence_number(static_cast<std::uint32_t>(i));
        std::vector<std::uint8_t> data(BYTES);
        for (std::size_t j = 0; j < BYTES; ++j) {
            data[j] = static_cast<std::uint8_t>(i + j * 7);
        }
        msg.data(std::move(data));
        ASSERT_TRUE(writer->write(&msg));
        std::this_thread::sleep_for(20ms);  // one sample at a time in the base camp's socket buffer
    }
    ASSERT_TRUE(wait_until([&] { return wan.count() >= N; })) << "got " << wan.count() << " of " << N;
    for (const auto& got : wan.received()) {
        const auto i = got.data.sequence_number();
        ASSERT_EQ(got.data.data().size(), BYTES);
        for (std::size_t j = 0; j < BYTES; j += 997) {
            ASSERT_EQ(got.data.data()[j], static_cast<std::uint8_t>(i + j * 7)) << "sample " << i << " byte " << j;
        }
    }
    expect_balanced();
}

INSTANTIATE_TEST_SUITE_P(WanMaxDatagram, LargeSampleTest,
                         ::testing::Values(core::WireModel::MAX_DATAGRAM_PAYLOAD_BYTES,
                                           core::WireModel::MAX_UDP_PAYLOAD_BYTES));

/// How the gateway's robot side may listen (RobotTransport): UDP alone (the default) or with shared memory.
enum class RobotMode { udp, shm };

/// By default the gateway's robot participant uses UDP alone, on loopback: a publisher with Fast DDS's default
/// transports then reaches it over UDP whatever user runs it. --robot-shm makes its readers offer shared memory
/// too. A publisher's sample arrives in each.
class RobotTransportTest : public GatewayIntegrationTest, public ::testing::WithParamInterface<RobotMode> {};

TEST_P(RobotTransportTest, ReadersOfferSharedMemoryOnlyWhenAskedTo) {
    const RobotMode mode = GetParam();
    ReaderLocatorWatcher watcher;
    TestParticipant robot(domains_.robot, TestParticipant::robot_qos(), &watcher);
    ASSERT_TRUE(robot.ok());
    GatewayConfig c = config();
    c.robot.shm = mode == RobotMode::shm;
    start_gateway(c);
    const std::string topic = topic_prefix_ + "robot_transport";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(robot), wan, &robot);
    ASSERT_NE(writer, nullptr);

    ASSERT_TRUE(wait_until([&] { return watcher.kinds(topic).has_value(); }, MATCH_TIMEOUT))
        << "the gateway's reader of " << topic << " was never discovered";
    const auto kinds = watcher.kinds(topic);
    EXPECT_EQ(kinds->count(LOCATOR_KIND_UDPv4), 1u);
    EXPECT_EQ(kinds->count(LOCATOR_KIND_SHM), mode == RobotMode::shm ? 1u : 0u);

    idl::PaperMessage msg;
    msg.data(std::vector<std::uint8_t>(64, 0x5a));
    ASSERT_TRUE(writer->write(&msg));
    EXPECT_TRUE(wait_until([&] { return wan.count() >= 1; })) << "the sample never arrived";
    gateway_.reset();  // before `robot`, whose writer the gateway's reader matched
}

INSTANTIATE_TEST_SUITE_P(RobotShm, RobotTransportTest, ::testing::Values(RobotMode::udp, RobotMode::shm),
                         [](const ::testing::TestParamInfo<RobotMode>& info) {
                             return std::string(info.param == RobotMode::shm ? "SharedMemoryAndUdp" : "UdpAlone");
                         });

/// A process with UDP alone on its host's addresses (no whitelist, no shared memory) announces the host's other
/// addresses, not 127.0.0.1, and hears discovery on the well-known port of its participant index. The gateway on
/// loopback finds it there and answers those addresses on 127.0.0.1: the way it reaches a process of another
/// user, whose shared memory it cannot use (test/system/cross_user_test.sh runs one).
TEST_F(GatewayIntegrationTest, AProcessWithUdpAloneOnItsHostsAddressesIsFoundAndHeard) {
    fdds::DomainParticipantQos udp_alone;
    udp_alone.transport().use_builtin_transports = false;
    udp_alone.transport().user_transports.push_back(
        std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>());
    TestParticipant robot(domains_.robot, udp_alone);
    ASSERT_TRUE(robot.ok());
    start_gateway(config());
    const std::string topic = topic_prefix_ + "udp_alone";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(robot), wan, &robot);
    ASSERT_NE(writer, nullptr);

    idl::PaperMessage msg;
    msg.data(std::vector<std::uint8_t>(64, 0x5a));
    ASSERT_TRUE(writer->write(&msg));
    EXPECT_TRUE(wait_until([&] { return wan.count() >= 1; })) << "the sample never arrived";
    gateway_.reset();
}

/// By default a burst's samples share datagrams on the WAN (DatagramCoalescer): Fast DDS's receiver reads
/// every sample of them, in order.
TEST_F(GatewayIntegrationTest, CoalescedBurstArrivesWholeAndInOrderInFewerDatagrams) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "coalesced";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    const auto before = gateway_->wan_datagrams();

    constexpr int N = 500;
    idl::PaperMessage msg;
    msg.data(std::vector<std::uint8_t>(41, 0x41));
    for (int i = 0; i < N; ++i) {
        msg.sequence_number(static_cast<std::uint32_t>(i));
        ASSERT_TRUE(writer->write(&msg));
    }
    ASSERT_TRUE(wait_until([&] { return wan.count() >= N; })) << "got " << wan.count() << " of " << N;
    const auto got = wan.received();
    for (int i = 0; i < N; ++i) {
        ASSERT_EQ(got[i].data.sequence_number(), static_cast<std::uint32_t>(i));
        ASSERT_EQ(got[i].data.data().size(), 41u);
    }
    const auto after = gateway_->wan_datagrams();
    EXPECT_EQ(after.messages - before.messages, static_cast<std::uint64_t>(N));
    EXPECT_LT(after.datagrams - before.datagrams, after.messages - before.messages);
    EXPECT_EQ(after.failed_datagrams, 0u);
    EXPECT_EQ(gateway_->wan_write_failures(), 0u);
    expect_balanced();
}

TEST_F(GatewayIntegrationTest, FollowsTheBaseCampsReceiverReportsAboutItself) {
    GatewayConfig c = config();
    c.receiver_reports = true;
    start_gateway(c);
    EXPECT_FALSE(gateway_->receiver_report());
    const std::string topic = topic_prefix_ + "reported";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    constexpr int N = 10;
    for (int i = 0; i < N; ++i) {
        idl::PaperMessage msg;
        msg.data(std::vector<std::uint8_t>(41, 1));
        ASSERT_TRUE(writer->write(&msg));
    }
    ASSERT_TRUE(wait_until([&] { return wan.count() >= N; })) << "got " << wan.count() << " of " << N;

    // The base camp tallies what came from the gateway's writer, as tm-basecamp record does, and reports it,
    // with a report about another gateway beside it.
    basecamp::DeliveryTally tally;
    std::uint64_t bytes = 0;
    for (const auto& got : wan.received()) {
        const auto& guid = got.info.sample_identity.writer_guid();
        basecamp::WriterGuid id;
        std::copy(std::begin(guid.guidPrefix.value), std::end(guid.guidPrefix.value), id.begin());
        std::copy(std::begin(guid.entityId.value), std::end(guid.entityId.value), id.begin() + 12);
        const std::uint64_t serialized = 4 + 8 + 4 + 4 + 41;  // encapsulation, generated_ns, sequence, length, data
        tally.add(id, got.info.sample_identity.sequence_number().to64long(), serialized);
        bytes += serialized;
    }
    auto totals = tally.totals();
    ASSERT_EQ(totals.size(), 1u);
    basecamp::ParticipantPrefix other{};
    other.fill(0xee);
    totals[other] = basecamp::DeliveryTotals{5, 500, 7};
    basecamp::ReceiverReporter reporter(basecamp_->participant());
    ASSERT_TRUE(wait_until([&] {
        reporter.publish(totals);  // best effort: repeated until the gateway's reader has matched and taken one
        return gateway_->receiver_report().has_value();
    })) << "the gateway never took a receiver report";
    const auto report = *gateway_->receiver_report();
    EXPECT_EQ(report.received_samples, static_cast<std::uint64_t>(N));
    EXPECT_EQ(report.received_bytes, bytes);
    EXPECT_EQ(report.lost_samples, 0u);
    EXPECT_EQ(report.in_flight_samples, 0u);  // all forwarded samples arrived
    EXPECT_GE(report.reports, 1u);
}

TEST_F(GatewayIntegrationTest, KeepsTheInstancesOfAKeyedTopic) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "keyed";
    auto& wan = listener<CollectingReader<idl::KeyedReading>>();
    auto* writer = bridge<idl::KeyedReadingPubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(gateway_->find_topic(topic)->keyed);

    std::map<std::uint32_t, fdds::InstanceHandle_t> robot_handles;
    constexpr int ROUNDS = 3;
    for (int round = 0; round < ROUNDS; ++round) {
        for (std::uint32_t sensor : {7u, 11u, 4242u}) {
            idl::KeyedReading r;
            r.sensor_id(sensor);
            r.value(round * 1.5);
            r.label("sensor-" + std::to_string(sensor));
            robot_handles[sensor] = writer->register_instance(&r);
            ASSERT_EQ(writer->write(&r, robot_handles[sensor]), ReturnCode_t::RETCODE_OK);
        }
    }
    ASSERT_TRUE(wait_until([&] { return wan.count() >= 3 * ROUNDS; })) << "got " << wan.count();
    std::map<std::uint32_t, std::set<fdds::InstanceHandle_t>> handles_by_sensor;
    for (const auto& r : wan.received()) {
        handles_by_sensor[r.data.sensor_id()].insert(r.info.instance_handle);
        EXPECT_EQ(r.data.label(), "sensor-" + std::to_string(r.data.sensor_id()));
    }
    ASSERT_EQ(handles_by_sensor.size(), 3u);
    std::set<fdds::InstanceHandle_t> distinct;
    for (const auto& [sensor, handles] : handles_by_sensor) {
        ASSERT_EQ(handles.size(), 1u) << "sensor " << sensor << " arrived as several instances";
        EXPECT_EQ(*handles.begin(), robot_handles[sensor]) << "the WAN instance is not the robot's";
        distinct.insert(*handles.begin());
    }
    EXPECT_EQ(distinct.size(), 3u);
    expect_balanced();
}

TEST_F(GatewayIntegrationTest, CarriesATypeOnlyThePublisherKnows) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "opaque";
    auto& wan = listener<CollectingReader<OpaqueBlob>>();
    auto* writer = bridge<OpaqueBlobType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    EXPECT_EQ(gateway_->find_topic(topic)->type_name, OpaqueBlobType::TYPE_NAME);

    OpaqueBlob blob;
    blob.id = 0xdeadbeef;
    for (int i = 0; i < 3000; ++i) {  // larger than one datagram's worth of fragment: DATA_FRAG on the WAN
        blob.bytes.push_back(static_cast<std::uint8_t>(i * 7));
    }
    ASSERT_TRUE(writer->write(&blob));
    ASSERT_TRUE(wait_until([&] { return wan.count() >= 1; }));
    const auto got = wan.received().front().data;
    EXPECT_EQ(got.id, blob.id);
    EXPECT_EQ(got.bytes, blob.bytes);
}

TEST_F(GatewayIntegrationTest, TakesTheTtlFromThePublishersLifespan) {
    start_gateway(config());
    const std::string topic = topic_prefix_ + "lifespan";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_, 3s), wan);
    ASSERT_NE(writer, nullptr);

    const auto bridged = gateway_->find_topic(topic);
    EXPECT_EQ(bridged->ttl.source, passthrough::TtlSource::publisher);
    EXPECT_EQ(bridged->ttl.ttl, base::Duration(3s));
    EXPECT_EQ(gateway_->wan_writer_lifespan(bridged->id), base::Duration(3s));
    PublisherWatcher::Seen seen;
    ASSERT_TRUE(wait_until([&] { return watcher_.find(topic, seen); }));
    EXPECT_EQ(seen.lifespan, eprosima::fastrtps::Duration_t(3, 0)) << "the base camp sees another Lifespan";
    EXPECT_EQ(seen.reliability, fdds::RELIABLE_RELIABILITY_QOS) << "the WAN writer must offer what the robot's did";
}

TEST_F(GatewayIntegrationTest, TakesTheTtlFromAnXmlProfileNamedAfterTheTopic) {
    const std::string topic = topic_prefix_ + std::to_string(::getpid()) + "/profiled";
    GatewayConfig c = config();
    c.qos_file = writer_profile_file(topic, 7, "");
    start_gateway(c);
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_, 3s), wan);
    ASSERT_NE(writer, nullptr);

    const auto bridged = gateway_->find_topic(topic);
    EXPECT_EQ(bridged->ttl.source, passthrough::TtlSource::profile) << "the profile must win over the publisher's 3 s";
    EXPECT_EQ(bridged->ttl.ttl, base::Duration(7s));
    PublisherWatcher::Seen seen;
    ASSERT_TRUE(wait_until([&] { return watcher_.find(topic, seen); }));
    EXPECT_EQ(seen.lifespan, eprosima::fastrtps::Duration_t(7, 0));
}

TEST_F(GatewayIntegrationTest, BridgesATopicTheQosFileDeclaresBeforeItsPublisherAppears) {
    const std::string topic = topic_prefix_ + std::to_string(::getpid()) + "/declared";
    GatewayConfig c = config();
    c.qos_file =
        writer_profile_file(topic, 2, "<topic><kind>NO_KEY</kind><dataType>tgw::idl::PaperMessage</dataType></topic>");
    start_gateway(c);
    // No publisher yet: the topic is bridged and its WAN writer announced from the start.
    ASSERT_TRUE(gateway_->wait_for_topic(topic, MATCH_TIMEOUT));
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_NE(basecamp_->make_reader(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                     wan_reader_qos(*basecamp_), &wan),
              nullptr);
    ASSERT_TRUE(wait_until([&] { return wan.matched.load() > 0; }, MATCH_TIMEOUT))
        << "the declared topic's WAN writer was not there before its publisher";

    auto& writer_matches = listener<MatchCounter>();
    auto* writer = robot_->make_writer(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                       robot_writer_qos(*robot_), &writer_matches);
    ASSERT_NE(writer, nullptr);
    wait_for_bridge(topic, writer_matches, wan.matched);
    ASSERT_FALSE(HasFatalFailure());
    EXPECT_EQ(gateway_->find_topic(topic)->lanes.size(), 1u) << "the reliable publisher took a lane of its own";
    EXPECT_EQ(gateway_->find_topic(topic)->ttl.ttl, base::Duration(2s));
    for (std::uint64_t i = 0; i < 10; ++i) {
        idl::PaperMessage msg;
        msg.generated_ns(i);
        ASSERT_TRUE(writer->write(&msg));
    }
    EXPECT_TRUE(wait_until([&] { return wan.count() >= 10; })) << "got " << wan.count();
}

TEST_F(GatewayIntegrationTest, ADeclaredTopicWhosePublisherRanBeforeTheGatewayCrossesOnceAsDeclared) {
    // A gateway restarted on a running robot: its publishers are there when its robot participant starts. The
    // declaration must still take them, so that each sample crosses once, with the file's QoS.
    const std::string topic = topic_prefix_ + std::to_string(::getpid()) + "/running";
    auto& writer_matches = listener<MatchCounter>();
    auto* writer = robot_->make_writer(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                       robot_writer_qos(*robot_), &writer_matches);
    ASSERT_NE(writer, nullptr);
    GatewayConfig c = config();
    c.qos_file =
        writer_profile_file(topic, 2, "<topic><kind>NO_KEY</kind><dataType>tgw::idl::PaperMessage</dataType></topic>");
    start_gateway(c);
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_NE(basecamp_->make_reader(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                     wan_reader_qos(*basecamp_), &wan),
              nullptr);
    wait_for_bridge(topic, writer_matches, wan.matched);
    ASSERT_FALSE(HasFatalFailure());
    EXPECT_EQ(gateway_->find_topic(topic)->lanes.size(), 1u) << "the running publisher took a lane of its own";
    PublisherWatcher::Seen seen;
    ASSERT_TRUE(wait_until([&] { return watcher_.find(topic, seen); }));
    EXPECT_EQ(seen.reliability, fdds::BEST_EFFORT_RELIABILITY_QOS) << "the WAN writer offers the file's QoS";
    constexpr std::uint64_t SAMPLES = 10;
    for (std::uint64_t i = 0; i < SAMPLES; ++i) {
        idl::PaperMessage msg;
        msg.generated_ns(i);
        ASSERT_TRUE(writer->write(&msg));
    }
    ASSERT_TRUE(wait_until([&] { return wan.count() >= SAMPLES; })) << "got " << wan.count();
    std::this_thread::sleep_for(500ms);  // a second copy of any would have come by now
    EXPECT_EQ(wan.count(), SAMPLES);
}

TEST_F(GatewayIntegrationTest, UsesTheDefaultTtlWhenNothingElseApplies) {
    GatewayConfig c = config();
    c.default_ttl = 9s;
    start_gateway(c);
    const std::string topic = topic_prefix_ + "no_lifespan";
    auto& writer_matches = listener<MatchCounter>();
    ASSERT_NE(robot_->make_writer(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                  robot_writer_qos(*robot_), &writer_matches),
              nullptr);
    ASSERT_TRUE(gateway_->wait_for_topic(topic, MATCH_TIMEOUT));
    const auto bridged = gateway_->find_topic(topic);
    EXPECT_EQ(bridged->ttl.source, passthrough::TtlSource::fallback);
    EXPECT_EQ(bridged->ttl.ttl, base::Duration(9s));
}

TEST_F(GatewayIntegrationTest, BridgesATopicThatAppearsAfterTheGatewayStarted) {
    start_gateway(config());
    const std::string first = topic_prefix_ + "first";
    auto& first_matches = listener<MatchCounter>();
    ASSERT_NE(robot_->make_writer(first, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                  robot_writer_qos(*robot_), &first_matches),
              nullptr);
    ASSERT_TRUE(gateway_->wait_for_topic(first, MATCH_TIMEOUT));

    // Only now, with the gateway running for a while, does the second topic appear, in a new participant.
    TestParticipant late_robot(domains_.robot, TestParticipant::robot_qos());
    ASSERT_TRUE(late_robot.ok());
    const std::string later = topic_prefix_ + "later";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(later, robot_writer_qos(late_robot), wan, &late_robot);
    ASSERT_NE(writer, nullptr);
    idl::PaperMessage msg;
    msg.generated_ns(42);
    ASSERT_TRUE(writer->write(&msg));
    ASSERT_TRUE(wait_until([&] { return wan.count() >= 1; }));
    EXPECT_EQ(wan.received().front().data.generated_ns(), 42u);
}

TEST_F(GatewayIntegrationTest, BridgesARos2TopicByItsDdsNames) {
    start_gateway(config());
    const std::string topic = "rt/chatter";  // the domain is unique to this test
    auto& wan = listener<CollectingReader<std_msgs::msg::dds_::String_>>();
    auto* writer = bridge<std_msgs::msg::dds_::String_PubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    EXPECT_EQ(gateway_->find_topic(topic)->type_name, "std_msgs::msg::dds_::String_");

    std_msgs::msg::dds_::String_ hello;
    hello.data("hello from the robot");
    ASSERT_TRUE(writer->write(&hello));
    ASSERT_TRUE(wait_until([&] { return wan.count() >= 1; }));
    EXPECT_EQ(wan.received().front().data.data(), "hello from the robot");
}

TEST_F(GatewayIntegrationTest, DeniedTopicsAreNotBridged) {
    GatewayConfig c = config();
    c.deny = {"*/secret*"};
    start_gateway(c);
    const std::string secret = topic_prefix_ + "secret_plans";
    const std::string open = topic_prefix_ + "open";
    auto& m1 = listener<MatchCounter>();
    auto& m2 = listener<MatchCounter>();
    ASSERT_NE(robot_->make_writer(secret, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                  robot_writer_qos(*robot_), &m1),
              nullptr);
    ASSERT_NE(
        robot_->make_writer(open, fdds::TypeSupport(new idl::PaperMessagePubSubType()), robot_writer_qos(*robot_), &m2),
        nullptr);
    ASSERT_TRUE(gateway_->wait_for_topic(open, MATCH_TIMEOUT));
    EXPECT_FALSE(gateway_->find_topic(secret));
    EXPECT_EQ(m1.matched.load(), 0);
}

TEST_F(GatewayIntegrationTest, WritesTheQueueToTheLogOnShutdown) {
    GatewayConfig c = config();
    c.log_file = temp_file(".db");
    c.scheduler.initial_rate_bps = 1000;  // about one sample a second: the rest waits in the queue
    c.default_ttl = 60s;
    start_gateway(c);
    const std::string topic = topic_prefix_ + "slow";
    auto& writer_matches = listener<MatchCounter>();
    auto* writer = robot_->make_writer(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                       robot_writer_qos(*robot_), &writer_matches);
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(gateway_->wait_for_topic(topic, MATCH_TIMEOUT));
    ASSERT_TRUE(wait_until([&] { return writer_matches.matched.load() > 0; }, MATCH_TIMEOUT));

    constexpr std::uint64_t N = 20;
    for (std::uint64_t i = 0; i < N; ++i) {
        idl::PaperMessage msg;
        msg.generated_ns(i);
        msg.data(std::vector<std::uint8_t>(41, 1));
        ASSERT_TRUE(writer->write(&msg));
    }
    const core::TopicId id = gateway_->find_topic(topic)->id;
    ASSERT_TRUE(wait_until([&] { return gateway_->counters(id).received >= N; }));
    EXPECT_GT(gateway_->queued_samples(), 0u);
    expect_balanced();

    gateway_->stop();
    const core::TopicCounters after = gateway_->counters(id);
    EXPECT_EQ(after.queued, 0u);
    EXPECT_EQ(after.received, N);
    EXPECT_EQ(after.received, after.forwarded + after.dropped_total());
    const std::uint64_t shutdown = after.dropped_for(core::DropReason::shutdown);
    EXPECT_GT(shutdown, 0u);
    EXPECT_EQ(gateway_->logged(), after.dropped_total());

    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open_v2(c.log_file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
    sqlite3_stmt* stmt = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db,
                                 "SELECT COUNT(*), COUNT(DISTINCT type_name), MIN(topic) FROM dropped_samples "
                                 "WHERE reason = 'shutdown'",
                                 -1, &stmt, nullptr),
              SQLITE_OK);
    ASSERT_EQ(sqlite3_step(stmt), SQLITE_ROW);
    EXPECT_EQ(static_cast<std::uint64_t>(sqlite3_column_int64(stmt, 0)), shutdown);
    EXPECT_EQ(sqlite3_column_int64(stmt, 1), 1);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(sqlite3_column_text(stmt, 2))), topic);
    sqlite3_finalize(stmt);
    sqlite3_close(db);
}

TEST_F(GatewayIntegrationTest, EverySampleIsForwardedQueuedOrLogged) {
    GatewayConfig c = config();
    c.log_file = temp_file(".db");
    start_gateway(c);
    const std::string topic = topic_prefix_ + "overload";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_, 1s), wan);
    ASSERT_NE(writer, nullptr);
    // Discovery was charged at the fast rate; now the slow link.
    gateway_->set_rate(20000);

    // 200 D-sized samples at once on a 20,000 bit/s link with a 1 s TTL: most cannot be sent.
    constexpr std::uint64_t N = 200;
    for (std::uint64_t i = 0; i < N; ++i) {
        idl::PaperMessage msg;
        msg.generated_ns(i);
        msg.data(std::vector<std::uint8_t>(1016, 2));
        ASSERT_TRUE(writer->write(&msg));
    }
    const core::TopicId id = gateway_->find_topic(topic)->id;
    ASSERT_TRUE(wait_until([&] { return gateway_->counters(id).received >= N; }));
    expect_balanced();
    ASSERT_TRUE(wait_until([&] { return gateway_->queued_samples() == 0; }, 5s));
    gateway_->stop();
    const core::TopicCounters after = gateway_->counters(id);
    EXPECT_EQ(after.received, N);
    EXPECT_EQ(after.queued, 0u);
    EXPECT_EQ(after.received, after.forwarded + after.dropped_total());
    EXPECT_GT(after.forwarded, 0u);
    EXPECT_GT(after.dropped_total(), 0u);
    EXPECT_EQ(gateway_->logged(), after.dropped_total());
    EXPECT_EQ(gateway_->wan_write_failures(), 0u);
    EXPECT_LE(wan.count(), after.forwarded);
}

}  // namespace
}  // namespace tgw::test
