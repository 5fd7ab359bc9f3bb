// DDS Security on the WAN domain with real participants on loopback and the identities scripts/make-certs makes
// (the tgw_certs fixture): the legitimate base camp gets every sample, in standard and compact mode; an identity
// of another CA gets nothing; an identity whose permissions exclude a topic gets nothing of it, and the rest.
// Each test asserts on samples received, not only on matching.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>

#include "GatewayStatusPubSubTypes.h"
#include "PaperWorkloadPubSubTypes.h"
#include "ReceiverReportPubSubTypes.h"
#include "base/dds_security.hpp"
#include "base/security_files.hpp"
#include "base/wan_address.hpp"
#include "basecamp/capture/backfill_archive.hpp"
#include "basecamp/capture/recorder.hpp"
#include "basecamp/recording/sample_store.hpp"
#include "basecamp/sample/sample_consumer.hpp"
#include "gateway/dds/wan_router.hpp"
#include "test/integration/relay_fixture.hpp"
#include "wire/receiver_report_topic.hpp"
#include "wire/status_topic.hpp"

namespace tgw::test {
namespace {

/// Keeps what a Recorder takes, per topic.
class KeptSamples final : public basecamp::SampleConsumer {
  public:
    void add_topic(basecamp::TopicRecord) override {}
    void add(basecamp::SampleRecord sample) override {
        std::lock_guard<std::mutex> lock(mutex_);
        by_topic_[sample.topic].push_back(std::move(sample.payload));
    }
    std::size_t count(const std::string& topic) const {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = by_topic_.find(topic);
        return it == by_topic_.end() ? 0 : it->second.size();
    }
    std::size_t topics() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return by_topic_.size();
    }

  private:
    mutable std::mutex mutex_;
    std::map<std::string, std::vector<std::vector<std::uint8_t>>> by_topic_;
};

/// The participants a participant has discovered, by GUID prefix.
class ParticipantsSeen final : public fdds::DomainParticipantListener {
  public:
    void on_participant_discovery(fdds::DomainParticipant*,
                                  eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override {
        if (info.status == eprosima::fastrtps::rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT) {
            std::lock_guard<std::mutex> lock(mutex_);
            seen_.insert(info.info.m_guid.guidPrefix);
        }
    }
    bool has(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix) const {
        std::lock_guard<std::mutex> lock(mutex_);
        return seen_.count(prefix) != 0;
    }

  private:
    mutable std::mutex mutex_;
    std::set<eprosima::fastrtps::rtps::GuidPrefix_t> seen_;
};

class SecurityTest : public RelayTest {
  protected:
    static void SetUpTestSuite() {
        if (!std::filesystem::exists(identity("gateway") + "/permissions.p7s")) {
            const std::string command = std::string(TGW_MAKE_CERTS) + " " + TGW_TEST_CERTS + " >/dev/null";
            ASSERT_EQ(std::system(command.c_str()), 0) << command;
        }
    }

    void TearDown() override {
        for (auto& running : recorders_) {
            running->stop.store(true);
            if (running->thread.joinable())
                running->thread.join();
            running->recorder.reset();
        }
        if (!expected_errors_.empty()) {
            // A refused participant or endpoint is an error in Fast DDS's log: expected here, and only these.
            gateway_.reset();
            basecamp_.reset();
            std::string others;
            for (const std::string& e : ErrorLogCounter::instance().take_errors()) {
                const bool expected = std::any_of(expected_errors_.begin(), expected_errors_.end(),
                                                  [&](const std::string& start) { return e.rfind(start, 0) == 0; });
                if (!expected)
                    others += e + "\n";
            }
            EXPECT_TRUE(others.empty()) << "Fast DDS logged unexpected errors:\n" << others;
        }
        RelayTest::TearDown();
    }

    static std::string identity(const std::string& name) { return std::string(TGW_TEST_CERTS) + "/" + name; }

    static base::SecurityFiles files_of(const std::string& name) {
        return base::SecurityFiles::load(identity(name), "--security");
    }

    /// `qos` with DDS Security as the identity `name`.
    static fdds::DomainParticipantQos secured(fdds::DomainParticipantQos qos, const std::string& name) {
        base::apply_dds_security(qos, files_of(name));
        return qos;
    }

    /// The gateway as DIR/gateway, announcing itself to the test's base-camp participant and to the ports of the
    /// WAN domain's first participants on loopback: a Recorder listens on its participant id's port, which Fast DDS
    /// picks past those this process made before.
    GatewayConfig secured_config() const {
        GatewayConfig c = config();
        c.wan_security = identity("gateway");
        c.scheduler.wire = core::WireModel::for_max_datagram(dds::SECURE_MIN_DATAGRAM_BYTES);
        c.wan_peers.push_back("127.0.0.1");
        c.wan_peer_participants = GatewayConfig::MAX_WAN_PEER_PARTICIPANTS;
        return c;
    }

    /// The test's base-camp participant (its reader of each bridged topic) as the identity `name`.
    void secured_basecamp(const std::string& name) {
        basecamp_ = std::make_unique<TestParticipant>(
            domains_.wan, secured(TestParticipant::wan_qos(domains_.wan_reader_port, domains_.gateway_wan_port), name),
            &watcher_);
        ASSERT_TRUE(basecamp_->ok()) << "no secured participant as " << name;
    }

    /// The relay as DIR/basecamp on the WAN; the camp's own domain plain. With `archive`, it records backfill
    /// into `store` (relay --out).
    void start_secured_relay(basecamp::SampleStore* store = nullptr, basecamp::BackfillArchive* archive = nullptr) {
        relay_ = std::make_unique<basecamp::Relay>(
            domains_.wan,
            secured(TestParticipant::wan_qos(domains_.wan_reader_port, domains_.gateway_wan_port), "basecamp"),
            local_domain_, fdds::PARTICIPANT_QOS_DEFAULT, store, 1s);
        if (archive != nullptr)
            relay_->archive_backfill(*archive);
        relay_thread_ = std::thread([this] { relay_->run(std::chrono::minutes(5), stop_relay_); });
    }

    struct RunningRecorder {
        KeptSamples kept;
        std::unique_ptr<basecamp::Recorder> recorder;
        std::thread thread;
        std::atomic<bool> stop{false};
    };

    /// tm-basecamp record as the identity `name`, unicast to the gateway on loopback.
    RunningRecorder& start_recorder(const std::string& name, base::Duration report_period = base::Duration::zero()) {
        auto running = std::make_unique<RunningRecorder>();
        base::PeerTransport transport;
        transport.peers = {"127.0.0.1"};
        transport.interface = "127.0.0.1";
        running->recorder =
            std::make_unique<basecamp::Recorder>(domains_.wan, transport, running->kept, report_period, files_of(name));
        RunningRecorder& r = *running;
        running->thread = std::thread([&r] { r.recorder->run(std::chrono::minutes(5), r.stop); });
        recorders_.push_back(std::move(running));
        return r;
    }

    /// Writes `n` PaperMessages whose 41 bytes are their number.
    static void publish(fdds::DataWriter* writer, std::uint32_t n) {
        for (std::uint32_t i = 0; i < n; ++i) {
            idl::PaperMessage m;
            m.generated_ns(i);
            m.data(std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
            ASSERT_EQ(writer->write(&m), true);
        }
    }

    static void expect_intact(const CollectingReader<idl::PaperMessage>& reader, std::uint32_t n) {
        std::set<std::uint64_t> seen;
        for (const auto& r : reader.received()) {
            EXPECT_EQ(r.data.data(), std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(r.data.generated_ns())));
            seen.insert(r.data.generated_ns());
        }
        EXPECT_EQ(seen.size(), n);
    }

    /// How the Fast DDS errors a test expects start (category: message); none: every error fails the test.
    std::vector<std::string> expected_errors_;
    std::vector<std::unique_ptr<RunningRecorder>> recorders_;
};

constexpr std::uint32_t N = 20;

TEST_F(SecurityTest, SecuredBaseCampGetsEverySampleTheStatusAndSendsItsReports) {
    secured_basecamp("basecamp");
    GatewayConfig c = secured_config();
    c.status_period = 200ms;
    c.receiver_reports = true;
    auto& statuses = listener<CollectingReader<idl::GatewayStatus>>();
    fdds::DataReaderQos reliable = basecamp_->default_reader_qos();
    reliable.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    ASSERT_NE(basecamp_->make_reader(wire::STATUS_TOPIC, fdds::TypeSupport(new idl::GatewayStatusPubSubType()),
                                     reliable, &statuses),
              nullptr);
    start_gateway(c);
    // tm-basecamp record too, as DIR/basecamp: it reads every topic and reports on tgw/receiver_report.
    RunningRecorder& recorder = start_recorder("basecamp", 200ms);

    const std::string topic = topic_prefix_ + "paper";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    // Both ends: a volatile reader gets nothing its writer sent before the reader matched it.
    ASSERT_TRUE(wait_until(
        [&] {
            return gateway_->wan_matched_readers(gateway_->find_topic(topic)->id) >= 2 &&
                   recorder.recorder->matched_writers(topic) > 0;
        },
        MATCH_TIMEOUT))
        << "the recorder and the gateway's writer of " << topic << " never matched (" << gateway_->wan_participants()
        << " base-camp participants)";
    publish(writer, N);

    ASSERT_TRUE(wait_until([&] { return wan.count() >= N && recorder.kept.count(topic) >= N; }))
        << "base camp " << wan.count() << ", recorder " << recorder.kept.count(topic) << " of " << N;
    expect_intact(wan, N);
    EXPECT_EQ(recorder.kept.count(topic), N);
    ASSERT_TRUE(wait_until([&] { return statuses.count() > 0; })) << "no status on " << wire::STATUS_TOPIC;
    ASSERT_TRUE(wait_until([&] {
        const auto report = gateway_->receiver_report();
        return report && report->received_samples >= N;
    })) << "the gateway never read the recorder's report of all "
        << N << " samples on tgw/receiver_report";
    expect_balanced();
}

TEST_F(SecurityTest, SecuredRelayGetsEverySampleInCompactMode) {
    GatewayConfig c = secured_config();
    c.compact_wan = true;
    start_gateway(c);
    start_secured_relay();
    const std::string topic = topic_prefix_ + "paper";
    auto& reader = listener<CollectingReader<idl::PaperMessage>>();
    local_reader<idl::PaperMessagePubSubType>(topic, local_->default_reader_qos(), reader);
    auto* writer = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(false));
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(
        wait_until([&] { return reader.matched.load() > 0 && relay_->local_readers(topic) > 0; }, 3 * MATCH_TIMEOUT))
        << "the relay never made the local writer of " << topic << " from the secured catalog";
    ASSERT_TRUE(
        wait_until([&] { return gateway_->wan_matched_readers(gateway_->find_topic(topic)->id) > 0; }, MATCH_TIMEOUT))
        << "the secured relay never matched the gateway's bundle writer";
    publish(writer, N);

    ASSERT_TRUE(wait_until([&] { return reader.count() >= N; })) << "got " << reader.count() << " of " << N;
    expect_intact(reader, N);
    ASSERT_TRUE(gateway_->wan_bundles());
    EXPECT_GT(gateway_->wan_bundles()->bundles, 0u);
    EXPECT_EQ(relay_->relayed()[topic], N);
    expect_balanced();
}

TEST_F(SecurityTest, SecuredRelayArchivesWhatTheLogKeptByBackfill) {
    // make-certs grants the camp tgw/backfill_ack: without it the gateway would never hear what the camp stored.
    GatewayConfig c = secured_config();
    const std::string log_path = temp_file("-robot.db");
    c.log_file = log_path;
    c.backfill = true;
    start_gateway(c);
    const std::string camp_path = temp_file("-camp.db");
    basecamp::SampleStore store(camp_path, "--out", 50);
    basecamp::BackfillArchive archive(store);
    start_secured_relay(&store, &archive);
    const std::string topic = topic_prefix_ + "expiring";
    auto* writer =
        robot_writer<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_, std::chrono::milliseconds(300)));
    ASSERT_NE(writer, nullptr);
    // The camp and the robot know each other before the radio goes (their handshake done).
    ASSERT_TRUE(wait_until([&] { return gateway_->wan_matched_readers(gateway_->find_topic(topic)->id) > 0; },
                           3 * MATCH_TIMEOUT))
        << "the secured relay never matched the gateway's writer of " << topic;

    gateway_->set_wan_link_up(false);  // the radio goes: the samples expire into the log
    publish(writer, N);
    const auto expired = [&] {
        return gateway_->counters(gateway_->find_topic(topic)->id).dropped_for(core::DropReason::expired);
    };
    ASSERT_TRUE(wait_until([&] { return expired() >= N; })) << "expired: " << expired();
    gateway_->set_wan_link_up(true);

    // 60 s: the backfill endpoints' secured match may still be under way when the radio goes; it then completed
    // about 15 s after the radio came back in 2 of 6 runs (6 s otherwise).
    ASSERT_TRUE(wait_until([&] { return archive.acknowledged() >= N; }, 60s))
        << "acknowledged " << archive.acknowledged() << " of " << N << "; the camp received " << archive.received()
        << ", the gateway sent " << gateway_->backfill_summary()->counts.sent << ", its backlog "
        << gateway_->backfill_summary()->backlog.rows << " rows";
    ASSERT_TRUE(wait_until([&] { return gateway_->backfill_summary()->counts.acknowledged >= N; }, 10s))
        << "the gateway heard " << gateway_->backfill_summary()->counts.acknowledged << " of " << N
        << " acknowledgements over the secured WAN";
    store.flush();
    EXPECT_EQ(archive.received() - store.duplicate_backfill_rows(), N) << "each row stored once";
    stop_relay_.store(true);  // before the archive and store it writes into go
    relay_thread_.join();
    relay_.reset();
}

TEST_F(SecurityTest, RecorderOfAnotherCaGetsNothing) {
    expected_errors_ = {"SECURITY: "};
    secured_basecamp("basecamp");
    start_gateway(secured_config());
    RunningRecorder& intruder = start_recorder("intruder");

    const std::string topic = topic_prefix_ + "paper";
    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    publish(writer, N);
    ASSERT_TRUE(wait_until([&] { return wan.count() >= N; })) << "got " << wan.count() << " of " << N;
    expect_intact(wan, N);

    // Everything went to the base camp while the intruder was on the domain: it learnt of no topic, took no sample,
    // and the gateway knows one base-camp participant only.
    EXPECT_EQ(intruder.kept.topics(), 0u);
    EXPECT_TRUE(intruder.recorder->received().empty());
    EXPECT_EQ(gateway_->wan_participants(), 1u);
    EXPECT_EQ(gateway_->wan_matched_readers(gateway_->find_topic(topic)->id), 1);
}

TEST_F(SecurityTest, LimitedIdentityGetsNothingOfTheTopicItsPermissionsExclude) {
    // Its recorder's reader of the restricted topic is refused at creation.
    expected_errors_ = {"SECURITY: ", "DATA_READER: Problem creating associated Reader"};
    secured_basecamp("basecamp");
    start_gateway(secured_config());
    RunningRecorder& limited = start_recorder("limited");

    // DIR/limited may subscribe to every topic but those matching *restricted*.
    const std::string open = topic_prefix_ + "open";
    const std::string restricted = topic_prefix_ + "restricted";
    auto& open_wan = listener<CollectingReader<idl::PaperMessage>>();
    auto& restricted_wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* open_writer = bridge<idl::PaperMessagePubSubType>(open, robot_writer_qos(*robot_), open_wan);
    auto* restricted_writer =
        bridge<idl::PaperMessagePubSubType>(restricted, robot_writer_qos(*robot_), restricted_wan);
    ASSERT_TRUE(open_writer && restricted_writer);
    ASSERT_TRUE(wait_until(
        [&] {
            return gateway_->wan_matched_readers(gateway_->find_topic(open)->id) >= 2 &&
                   limited.recorder->matched_writers(open) > 0;
        },
        MATCH_TIMEOUT))
        << "the limited recorder and the gateway's writer of " << open << " never matched";
    publish(open_writer, N);
    publish(restricted_writer, N);

    ASSERT_TRUE(wait_until([&] {
        return open_wan.count() >= N && restricted_wan.count() >= N && limited.kept.count(open) >= N;
    })) << "base camp "
        << open_wan.count() << " and " << restricted_wan.count() << ", limited " << limited.kept.count(open) << " of "
        << N;
    expect_intact(restricted_wan, N);
    EXPECT_EQ(limited.kept.count(open), N);
    EXPECT_EQ(limited.kept.count(restricted), 0u);
    // The gateway's writer of the restricted topic has the base camp's reader alone.
    EXPECT_EQ(gateway_->wan_matched_readers(gateway_->find_topic(restricted)->id), 1);
}

TEST_F(SecurityTest, PlainParticipantGetsNothingAndItsReportsNeverReachTheGateway) {
    expected_errors_ = {"SECURITY: "};
    secured_basecamp("basecamp");
    GatewayConfig c = secured_config();
    c.receiver_reports = true;
    start_gateway(c);
    const std::string topic = topic_prefix_ + "paper";
    // A participant without security on the WAN domain, announcing itself to the gateway: a reader of the robot's
    // topic, and a writer of receiver reports that tell the gateway a million samples arrived.
    auto& seen = listener<ParticipantsSeen>();
    TestParticipant plain(
        domains_.wan,
        TestParticipant::wan_qos(base::metatraffic_unicast_port(domains_.wan, 62), domains_.gateway_wan_port), &seen);
    ASSERT_TRUE(plain.ok());
    // In touch: the gateway's announcements, which are never protected, reach it.
    ASSERT_TRUE(wait_until([&] { return seen.has(gateway_->wan_guid_prefix()); }, MATCH_TIMEOUT))
        << "the plain participant never heard of the gateway";
    auto& eavesdropped = listener<CollectingReader<idl::PaperMessage>>();
    ASSERT_NE(plain.make_reader(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()), plain.default_reader_qos(),
                                &eavesdropped),
              nullptr);
    fdds::DataWriter* forged =
        plain.make_writer(wire::RECEIVER_REPORT_TOPIC, fdds::TypeSupport(new idl::ReceiverReportPubSubType()),
                          plain.default_writer_qos());
    ASSERT_NE(forged, nullptr);
    idl::ReceiverReport report;
    const auto prefix = gateway_->wan_guid_prefix();
    std::array<std::uint8_t, 12> prefix_bytes{};
    std::copy(std::begin(prefix.value), std::end(prefix.value), prefix_bytes.begin());
    report.gateway_prefix(prefix_bytes);
    report.received_samples(1'000'000);

    auto& wan = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = bridge<idl::PaperMessagePubSubType>(topic, robot_writer_qos(*robot_), wan);
    ASSERT_NE(writer, nullptr);
    // A forged report with each sample, while the secured base camp receives them all.
    for (std::uint32_t i = 0; i < N; ++i) {
        idl::PaperMessage m;
        m.generated_ns(i);
        m.data(std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
        ASSERT_TRUE(writer->write(&m));
        forged->write(&report);  // matched by no one: it goes nowhere, which is the point
    }
    ASSERT_TRUE(wait_until([&] { return wan.count() >= N; })) << "got " << wan.count() << " of " << N;
    expect_intact(wan, N);

    // With the gateway and the base camp plain (tried by hand on 2026-11-25), the same participant took all 20
    // samples, its report reached the gateway, and the gateway counted it as a second base-camp participant.
    EXPECT_EQ(eavesdropped.count(), 0u);
    EXPECT_EQ(eavesdropped.matched.load(), 0);
    EXPECT_FALSE(gateway_->receiver_report().has_value()) << "a forged receiver report reached the gateway";
    EXPECT_EQ(gateway_->wan_participants(), 1u);
}

}  // namespace
}  // namespace tgw::test
