// The compact WAN mode end to end on real participants: a robot publisher, a Gateway in --wan-mode compact, the
// relay unpacking the bundles into the camp's domain, and plain subscribers of the original types there.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "CompactWanPubSubTypes.h"
#include "GatewayStatusPubSubTypes.h"
#include "KeyedReadingPubSubTypes.h"
#include "PaperWorkloadPubSubTypes.h"
#include "base/wan_address.hpp"
#include "basecamp/relay/compact_unpacker.hpp"
#include "compact/bundle_codec.hpp"
#include "passthrough/dds_time.hpp"
#include "test/integration/raw_sample_type.hpp"
#include "test/integration/relay_fixture.hpp"
#include "wire/compact_topics.hpp"
#include "wire/status_topic.hpp"

namespace tgw::test {
namespace {

class CompactWanTest : public RelayTest {
  protected:
    GatewayConfig compact_config() const {
        GatewayConfig c = config();
        c.compact_wan = true;
        return c;
    }

    /// Writes `n` PaperMessages numbered from `first`, stamped now, remembering the stamps.
    void publish_paper(fdds::DataWriter* writer, std::uint32_t first, std::uint32_t n) {
        for (std::uint32_t i = first; i < first + n; ++i) {
            idl::PaperMessage m;
            m.generated_ns(i);
            m.data(std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
            stamps_[i] = stamp_now();
            ASSERT_EQ(writer->write_w_timestamp(&m, fdds::HANDLE_NIL, stamps_[i]), ReturnCode_t::RETCODE_OK);
        }
    }

    /// Both ends of the relay's local writer of `topic` have matched: a best-effort writer sends a reader
    /// nothing before it has matched it from its own side. False on timeout.
    bool local_writer_matched(const std::string& topic) {
        return wait_until([&] { return relay_->local_readers(topic) > 0; }, MATCH_TIMEOUT);
    }

    /// A plain best-effort reader of `topic` on the camp's domain and the robot's writer of it, once every hop
    /// between them has matched (the relay's local writer from both sides, the gateway's bundle writer); the
    /// writer, or nullptr after a failed assertion.
    fdds::DataWriter* paper_path(const std::string& topic, CollectingReader<idl::PaperMessage>& reader) {
        local_reader<idl::PaperMessagePubSubType>(topic, local_->default_reader_qos(), reader);
        auto* writer = robot_writer<idl::PaperMessagePubSubType>(topic, writer_qos(false));
        const bool matched =
            writer != nullptr && wait_until([&] { return reader.matched.load() > 0; }, 3 * MATCH_TIMEOUT) &&
            local_writer_matched(topic) &&
            wait_until([&] { return gateway_->wan_matched_readers(gateway_->find_topic(topic)->id) > 0; },
                       MATCH_TIMEOUT);
        EXPECT_TRUE(matched) << "the path of " << topic << " never matched end to end";
        return matched ? writer : nullptr;
    }

    /// The gateway started with `c`, the relay, and paper_path(topic, reader).
    fdds::DataWriter* started_paper_path(const GatewayConfig& c, const std::string& topic,
                                         CollectingReader<idl::PaperMessage>& reader) {
        start_gateway(c);
        start_relay();
        return paper_path(topic, reader);
    }

    std::map<std::uint64_t, eprosima::fastrtps::Time_t> stamps_;
};

TEST_F(CompactWanTest, PlainSubscribersOfTheOriginalTypesGetPayloadKeyAndTimestampIntact) {
    // A link slow enough that a burst queues: what waits leaves in shared bundles.
    GatewayConfig c = compact_config();
    c.scheduler.initial_rate_bps = 200'000;
    start_gateway(c);
    start_relay();
    const std::string paper = topic_prefix_ + "paper";
    const std::string keyed = topic_prefix_ + "keyed";

    // Fast DDS's defaults (best effort) for one, a ROS 2-like reliable keep-last reader for the keyed topic.
    auto& paper_reader = listener<CollectingReader<idl::PaperMessage>>();
    local_reader<idl::PaperMessagePubSubType>(paper, local_->default_reader_qos(), paper_reader);
    fdds::DataReaderQos reliable = local_->default_reader_qos();
    reliable.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    reliable.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    reliable.history().depth = 100;
    auto& keyed_reader = listener<CollectingReader<idl::KeyedReading>>();
    local_reader<idl::KeyedReadingPubSubType>(keyed, reliable, keyed_reader);

    auto* paper_writer = robot_writer<idl::PaperMessagePubSubType>(paper, writer_qos(false));
    auto* keyed_writer = robot_writer<idl::KeyedReadingPubSubType>(keyed, writer_qos(false));
    ASSERT_TRUE(paper_writer && keyed_writer);
    // The relay learns both topics from the catalog and makes their local writers, which the readers match.
    for (auto* matched : {&paper_reader.matched, &keyed_reader.matched}) {
        ASSERT_TRUE(wait_until([&] { return matched->load() > 0; }, 3 * MATCH_TIMEOUT))
            << "a local reader never matched a writer the relay made from the catalog";
    }
    ASSERT_TRUE(local_writer_matched(paper) && local_writer_matched(keyed));
    ASSERT_TRUE(
        wait_until([&] { return gateway_->wan_matched_readers(gateway_->find_topic(paper)->id) > 0; }, MATCH_TIMEOUT))
        << "the relay never matched the gateway's bundle writer";

    constexpr std::uint32_t N = 40;
    std::map<std::uint32_t, fdds::InstanceHandle_t> robot_handles;
    publish_paper(paper_writer, 0, N);
    for (std::uint32_t i = 0; i < N; ++i) {
        idl::KeyedReading r;
        r.sensor_id(i % 4);
        r.value(i);
        robot_handles[i % 4] = keyed_writer->register_instance(&r);
        ASSERT_EQ(keyed_writer->write(&r, robot_handles[i % 4]), ReturnCode_t::RETCODE_OK);
    }
    ASSERT_TRUE(wait_until([&] { return paper_reader.count() >= N && keyed_reader.count() >= N; }))
        << "paper " << paper_reader.count() << ", keyed " << keyed_reader.count() << " of " << N;

    for (const auto& r : paper_reader.received()) {
        const std::uint64_t i = r.data.generated_ns();
        EXPECT_EQ(r.data.data(), std::vector<std::uint8_t>(41, static_cast<std::uint8_t>(i)));
        EXPECT_NEAR(static_cast<double>(ns_of(r.info.source_timestamp)), static_cast<double>(ns_of(stamps_[i])), 2)
            << "sample " << i << " lost its timestamp";
    }
    std::map<std::uint32_t, std::set<fdds::InstanceHandle_t>> instances;
    std::set<double> values;
    for (const auto& r : keyed_reader.received()) {
        instances[r.data.sensor_id()].insert(r.info.instance_handle);
        values.insert(r.data.value());
        EXPECT_EQ(static_cast<std::uint32_t>(r.data.value()) % 4, r.data.sensor_id());
    }
    EXPECT_EQ(values.size(), N);
    ASSERT_EQ(instances.size(), 4u);
    for (const auto& [sensor, handles] : instances) {
        ASSERT_EQ(handles.size(), 1u) << "sensor " << sensor << " arrived as several instances";
        EXPECT_EQ(*handles.begin(), robot_handles[sensor]);
    }
    // Packed: fewer bundles than samples (of both topics), and nothing the relay could not place.
    ASSERT_TRUE(gateway_->wan_bundles());
    EXPECT_LT(gateway_->wan_bundles()->bundles, N);
    EXPECT_GE(gateway_->wan_bundles()->entries, 2 * N);
    ASSERT_NE(relay_->compact(), nullptr);
    const basecamp::CompactUnpacker::Counts counts = relay_->compact()->counts();
    EXPECT_EQ(counts.rejected_bundles, 0u);
    EXPECT_EQ(counts.unknown_entries, 0u);
    EXPECT_EQ(relay_->relayed()[paper], N);
    EXPECT_EQ(relay_->relayed()[keyed], N);
    expect_balanced();
}

TEST_F(CompactWanTest, APictureLargerThanABundleLeavesInChunksAndArrivesWhole) {
    GatewayConfig c = compact_config();
    c.scheduler.initial_rate_bps = 400'000;
    const std::string pictures = topic_prefix_ + "pictures";
    auto& reader = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = started_paper_path(c, pictures, reader);
    ASSERT_NE(writer, nullptr);

    constexpr std::uint32_t N = 3;
    for (std::uint32_t i = 0; i < N; ++i) {
        idl::PaperMessage m;
        m.generated_ns(i);
        std::vector<std::uint8_t> frame(6'000);
        for (std::size_t k = 0; k < frame.size(); ++k)
            frame[k] = static_cast<std::uint8_t>(k * 7 + i);
        m.data(frame);
        ASSERT_TRUE(writer->write(&m));
    }
    ASSERT_TRUE(wait_until([&] { return reader.count() >= N; })) << reader.count() << " of " << N;
    for (const auto& r : reader.received()) {
        const std::uint32_t i = static_cast<std::uint32_t>(r.data.generated_ns());
        ASSERT_EQ(r.data.data().size(), 6'000u);
        for (std::size_t k = 0; k < r.data.data().size(); ++k) {
            ASSERT_EQ(r.data.data()[k], static_cast<std::uint8_t>(k * 7 + i)) << "byte " << k << " of picture " << i;
        }
    }
    // Five chunks or more each, every bundle within one datagram.
    EXPECT_GE(gateway_->wan_bundles()->bundles, 5 * N);
    EXPECT_EQ(relay_->compact()->counts().incomplete_samples, 0u);
    EXPECT_EQ(gateway_->counters(gateway_->find_topic(pictures)->id).forwarded, N);
    expect_balanced();
}

TEST_F(CompactWanTest, TheStatusTravelsCompressedAndReachesTheCampWhole) {
    GatewayConfig c = compact_config();
    c.status_period = 100ms;
    const std::string paper = topic_prefix_ + "paper";
    auto& reader = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = started_paper_path(c, paper, reader);
    ASSERT_NE(writer, nullptr);
    auto& statuses = listener<CollectingReader<idl::GatewayStatus>>();
    local_reader<idl::GatewayStatusPubSubType>(wire::STATUS_TOPIC, local_->default_reader_qos(), statuses);
    publish_paper(writer, 0, 10);
    ASSERT_TRUE(wait_until([&] { return reader.count() >= 10; })) << reader.count() << " of 10";
    // A status made after the samples left says so.
    ASSERT_TRUE(wait_until([&] {
        for (const auto& r : statuses.received()) {
            for (const idl::TopicStatus& t : r.data.topics()) {
                if (t.name() == paper && t.forwarded() == 10)
                    return true;
            }
        }
        return false;
    })) << statuses.count()
        << " statuses, none telling the 10 samples forwarded";
    const idl::GatewayStatus status = statuses.received().back().data;  // received() is a copy
    EXPECT_TRUE(status.compact_wan());
    EXPECT_GT(status.sensed_rate_bps(), 0.0);
    // What crossed the WAN was smaller than what the camp's reader got (a status of one topic, 232 bytes, takes
    // about 157; of the paper's four, 664 take about 270).
    idl::GatewayStatus copy = status;
    const std::size_t serialized = idl::GatewayStatusPubSubType().getSerializedSizeProvider(&copy)();
    const core::TopicCounters sent = gateway_->status_counters();
    ASSERT_GT(sent.forwarded, 0u);
    EXPECT_LT(sent.forwarded_payload_bytes / sent.forwarded, serialized * 3 / 4)
        << "a status of " << serialized << " bytes took " << sent.forwarded_payload_bytes / sent.forwarded;
    EXPECT_EQ(relay_->compact()->counts().undecodable_entries, 0u);
}

TEST_F(CompactWanTest, TheRelaysReceiverReportsCountTheGatewaysBundles) {
    GatewayConfig c = compact_config();
    c.receiver_reports = true;
    const std::string paper = topic_prefix_ + "paper";
    auto& reader = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = started_paper_path(c, paper, reader);
    ASSERT_NE(writer, nullptr);
    publish_paper(writer, 0, 10);
    ASSERT_TRUE(wait_until([&] { return reader.count() >= 10; })) << reader.count() << " of 10";
    // In compact mode the WAN samples are bundles: the report counts every one the gateway wrote (the status's
    // among them), and none lost.
    ASSERT_TRUE(wait_until([&] {
        const auto report = gateway_->receiver_report();
        return report && report->received_samples >= gateway_->wan_bundles()->bundles;
    })) << "the reports never caught up with the bundles written";
    EXPECT_EQ(gateway_->receiver_report()->lost_samples, 0u);
    EXPECT_GT(gateway_->receiver_report()->received_bytes, 10u * 60u);
}

// A bundle holds the time it was written, and its DDS message goes without the INFO_TS that would say it again
// (12 bytes a bundle): a plain reader of the bundles sees no source timestamp, and a measuring relay still times
// each bundle's crossing from the time inside it.
TEST_F(CompactWanTest, BundlesLeaveWithoutTheirDdsTimestampAndAMeasuringRelayTimesThemFromTheirOwn) {
    GatewayConfig c = compact_config();
    c.channel_grants = true;
    c.status_period = 1s;  // the relay counts the bundles of gateways it heard a status from
    start_gateway(c);
    start_relay(nullptr, 1s, {}, 30'000, true);
    TestParticipant other(domains_.wan, TestParticipant::wan_qos(base::metatraffic_unicast_port(domains_.wan, 62),
                                                                 domains_.gateway_wan_port));
    ASSERT_TRUE(other.ok());
    auto& bundles = listener<CollectingReader<wan::Bundle>>();
    fdds::DataReaderQos qos = other.default_reader_qos();
    qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
    ASSERT_NE(
        other.make_reader(wire::COMPACT_BUNDLE_TOPIC, fdds::TypeSupport(new wan::BundlePubSubType()), qos, &bundles),
        nullptr);
    const std::string paper = topic_prefix_ + "paper";
    auto& reader = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = paper_path(paper, reader);
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(wait_until([&] { return bundles.matched.load() > 0; }, 3 * MATCH_TIMEOUT));

    const std::int64_t before_ns = base::to_ns(base::WallClock::now());
    for (std::uint32_t i = 0; i < 20; ++i) {
        publish_paper(writer, i, 1);
        std::this_thread::sleep_for(50ms);
    }
    ASSERT_TRUE(wait_until([&] { return reader.count() >= 20 && bundles.count() >= 1; }))
        << reader.count() << " of 20 samples, " << bundles.count() << " bundles";
    ASSERT_TRUE(wait_until([&] {
        const auto reading = relay_->channel_reading();
        return reading && reading->queueing;
    })) << "the relay timed no bundle";

    for (const auto& received : bundles.received()) {
        EXPECT_FALSE(passthrough::to_wall_time(received.info.source_timestamp).has_value())
            << "a bundle came with its DDS timestamp";
        compact::Bundle decoded;
        ASSERT_EQ(compact::BundleCodec::decode(received.data.bytes().data(), received.data.bytes().size(), decoded),
                  compact::BundleError::none);
        ASSERT_TRUE(decoded.write_ns.has_value());
        EXPECT_GE(*decoded.write_ns, before_ns - 5'000'000'000) << "written before the test began";
        EXPECT_LE(*decoded.write_ns, base::to_ns(base::WallClock::now()));
    }
    EXPECT_LT(*relay_->channel_reading()->queueing, 250ms) << "nothing queues on loopback";
}

TEST_F(CompactWanTest, ARelayThatJoinsLateDecodesOnceTheCatalogReachesIt) {
    start_gateway(compact_config());
    const std::string paper = topic_prefix_ + "late";
    auto* writer = robot_writer<idl::PaperMessagePubSubType>(paper, writer_qos(false));
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(gateway_->wait_for_topic(paper, MATCH_TIMEOUT));
    publish_paper(writer, 0, 5);  // nobody at the base camp yet

    start_relay();
    auto& reader = listener<CollectingReader<idl::PaperMessage>>();
    local_reader<idl::PaperMessagePubSubType>(paper, local_->default_reader_qos(), reader);
    ASSERT_TRUE(wait_until([&] { return reader.matched.load() > 0; }, 3 * MATCH_TIMEOUT))
        << "the relay never made the local writer: the catalog did not reach it";
    ASSERT_TRUE(local_writer_matched(paper));
    ASSERT_TRUE(
        wait_until([&] { return gateway_->wan_matched_readers(gateway_->find_topic(paper)->id) > 0; }, MATCH_TIMEOUT));
    publish_paper(writer, 100, 10);
    const auto later = [&] {
        const auto received = reader.received();
        return std::count_if(received.begin(), received.end(),
                             [](const auto& r) { return r.data.generated_ns() >= 100; });
    };
    ASSERT_TRUE(wait_until([&] { return later() >= 10; })) << later() << " of 10";
    for (const auto& r : reader.received()) {
        const std::uint64_t generated = r.data.generated_ns();
        EXPECT_TRUE(generated < 5 || (generated >= 100 && generated < 110)) << generated;
    }
    // The five from before the relay joined were held for it, not sent to no one: sent once it matched, or
    // logged as no_reader had their TTL passed first.
    const core::TopicCounters c = gateway_->counters(gateway_->find_topic(paper)->id);
    EXPECT_EQ(c.forwarded + c.dropped_for(core::DropReason::no_reader), 15u);
}

TEST_F(CompactWanTest, TheRelayRejectsCorruptAndTruncatedBundlesAndGoesOn) {
    start_gateway(compact_config());
    start_relay();
    const std::string paper = topic_prefix_ + "paper";
    auto& reader = listener<CollectingReader<idl::PaperMessage>>();
    auto* writer = paper_path(paper, reader);
    ASSERT_NE(writer, nullptr);

    // Another participant on the WAN domain writes bundles that are not: cut short, a bit flipped, noise.
    TestParticipant other(domains_.wan, TestParticipant::wan_qos(base::metatraffic_unicast_port(domains_.wan, 62),
                                                                 domains_.wan_reader_port));
    ASSERT_TRUE(other.ok());
    auto& matches = listener<MatchCounter>();
    fdds::DataWriterQos qos = other.default_writer_qos();
    qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
    auto* forger =
        other.make_writer(wire::COMPACT_BUNDLE_TOPIC, fdds::TypeSupport(new wan::BundlePubSubType()), qos, &matches);
    ASSERT_NE(forger, nullptr);
    ASSERT_TRUE(wait_until([&] { return matches.matched.load() > 0; }, 3 * MATCH_TIMEOUT));
    compact::Bundle real;
    compact::BundleEntry entry;
    entry.topic_id = 0;
    entry.payload = {0x00, 0x01, 0x00, 0x00, 1, 2, 3, 4};
    real.entries.push_back(entry);
    std::vector<std::uint8_t> bytes;
    compact::BundleCodec::encode(real, bytes);
    std::vector<std::vector<std::uint8_t>> forged = {
        std::vector<std::uint8_t>(bytes.begin(), bytes.end() - 3), bytes, std::vector<std::uint8_t>(64, 0xa5), {}};
    forged[1][bytes.size() / 2] ^= 0x10;
    const auto forge = [&](const std::vector<std::uint8_t>& f) {
        wan::Bundle b;
        b.bytes(f);
        return forger->write(&b);
    };
    // The forger's best-effort writer matches as soon as it hears of the relay's reader, which may not have heard
    // of the writer yet and would drop what comes first: noise until the relay rejects one.
    const auto relay_rejected = [&] { return relay_->compact()->counts().rejected_bundles; };
    ASSERT_TRUE(wait_until(
        [&] { return forge(forged[2]) && wait_until([&] { return relay_rejected() > 0; }, std::chrono::seconds(1)); },
        3 * MATCH_TIMEOUT));
    const std::uint64_t primed = relay_rejected();
    for (const auto& f : forged)
        ASSERT_TRUE(forge(f));
    ASSERT_TRUE(wait_until([&] { return relay_rejected() >= primed + forged.size(); }))
        << relay_rejected() - primed << " of " << forged.size() << " rejected";

    // And samples that are not even CDR: an encapsulation that does not exist makes Fast-CDR throw inside take().
    TestParticipant raw(domains_.wan, TestParticipant::wan_qos(base::metatraffic_unicast_port(domains_.wan, 63),
                                                               domains_.wan_reader_port));
    ASSERT_TRUE(raw.ok());
    auto& raw_matches = listener<MatchCounter>();
    auto* raw_forger = raw.make_writer(wire::COMPACT_BUNDLE_TOPIC,
                                       fdds::TypeSupport(new RawSampleType(wan::BundlePubSubType().getName(), false)),
                                       qos, &raw_matches);
    ASSERT_NE(raw_forger, nullptr);
    ASSERT_TRUE(wait_until([&] { return raw_matches.matched.load() > 0; }, 3 * MATCH_TIMEOUT));
    for (const std::vector<std::uint8_t>& bytes :
         {std::vector<std::uint8_t>{0x00, 0x07, 0x00, 0x00, 4, 0, 0, 0, 1, 2, 3, 4},
          std::vector<std::uint8_t>{0x05, 0x01, 0x00, 0x00}, std::vector<std::uint8_t>{0x00, 0x01, 0x00, 0x00, 0xff}}) {
        RawSample sample{bytes, 0};
        ASSERT_TRUE(raw_forger->write(&sample));
    }

    publish_paper(writer, 0, 10);
    ASSERT_TRUE(wait_until([&] { return reader.count() >= 10; }))
        << reader.count() << " of 10 after the forgeries; the relay took " << relay_->compact()->counts().bundles
        << " bundles, " << relay_->compact()->counts().entries << " entries, relayed "
        << relay_->compact()->counts().relayed << ", could not place " << relay_->compact()->counts().unknown_entries
        << "; the gateway wrote " << gateway_->wan_bundles()->bundles << " bundles";
    EXPECT_EQ(relay_rejected(), primed + forged.size());
    // Fast DDS logs each sample it could not deserialize; that is the only error expected here.
    for (const std::string& error : ErrorLogCounter::instance().take_errors()) {
        EXPECT_NE(error.find("deserializ"), std::string::npos) << error;
    }
}

}  // namespace
}  // namespace tgw::test
